#!/usr/bin/env bash
# A node's launch-prefix: starts the node once SUBSCRIBER (a node name) subscribes to TOPIC, so
# that a scorer or a test started beside the launch file sees the node's first messages whatever
# the order in which ROS starts them. Without a SUBSCRIBER the node starts at once.
#   <node ... launch-prefix="$(find occlusion_env)/scripts/wait_for_subscriber.sh TOPIC $(arg scorer) --"/>
# Gives up after WAIT_FOR_SUBSCRIBER_TIMEOUT seconds (default 300) with a message and exit 1.
# Usage: wait_for_subscriber.sh TOPIC [SUBSCRIBER] -- COMMAND [ARGS...]
set -euo pipefail

usage() {
  echo "usage: wait_for_subscriber.sh TOPIC [SUBSCRIBER] -- COMMAND [ARGS...]" >&2
  exit 2
}

[[ $# -ge 2 ]] || usage
topic="$1"
shift
subscriber=""
if [[ "$1" != "--" ]]; then
  subscriber="$1"
  shift
fi
[[ $# -ge 2 && "$1" == "--" ]] || usage
shift

if [[ -n "$subscriber" ]]; then
  # rostopic info lists subscribers as " * /namespace/name (http://host:port/)".
  subscriber="/${subscriber#/}"
  timeout_s="${WAIT_FOR_SUBSCRIBER_TIMEOUT:-300}"
  deadline=$((SECONDS + timeout_s))
  until rostopic info "$topic" 2>/dev/null |
      awk -v name="$subscriber" '$1 == "*" && $2 == name { found = 1 } END { exit !found }'; do
    if ((SECONDS >= deadline)); then
      echo "wait_for_subscriber: $subscriber did not subscribe to $topic within ${timeout_s} s;" \
           "not starting $1" >&2
      exit 1
    fi
    sleep 0.5
  done
fi
exec "$@"
