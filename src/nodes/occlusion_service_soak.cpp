// occlusion_service_soak: drives the running simulator through its services for many steps and
// watches the simulator's resident memory and the step rate. Private parameters:
// serviceSoakOptionTable() (ros/service_probe_options.hpp; doc/PARAMETERS.md): with ~check, exits
// 1 when the simulator's memory grew more than ~max_growth_mb after warm-up, the last window's
// rate fell below ~min_rate_ratio of the first's, or a request failed.
// The simulator's PID comes from its ROS slave API (getPid); its memory is read from /proc, so
// both must run on the same machine. The loop is the in-process soak's (eval/soak.hpp), here on
// the services through EnvironmentClient.
#include <ros/network.h>
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <cstdio>
#include <string>
#include <vector>

#include "occlusion_env/eval/soak.hpp"
#include "occlusion_env/ros/environment_client.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"
#include "occlusion_env/ros/service_probe_options.hpp"

namespace {

/// The PID of the ROS node `name`, from the master's lookupNode and the node's getPid; 0 if not
/// found.
int nodePid(const std::string& name) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = name;
  if (!ros::master::execute("lookupNode", args, result, payload, true)) return 0;
  const std::string uri = payload;  // http://host:port/
  std::string host;
  std::uint32_t port = 0;
  if (!ros::network::splitURI(uri, host, port)) return 0;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue pid_args, pid_result;
  pid_args[0] = ros::this_node::getName();
  if (!client.execute("getPid", pid_args, pid_result) || pid_result.size() < 3) return 0;
  return static_cast<int>(pid_result[2]);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  ros::init(argc, argv, "occlusion_service_soak");
  ros::NodeHandle private_node("~");
  ServiceSoakOptions options;
  try {
    readParameters(private_node, serviceSoakOptionTable(), options);
  } catch (const ParameterError& error) {
    ROS_FATAL_STREAM(error.what());
    return 2;
  }
  warnAboutUnknownParameters(private_node, serviceSoakOptionTable());

  EnvironmentClient client{ros::NodeHandle(names::kNamespace)};
  try {
    client.connect();
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM("no simulator: " << error.what());
    return 1;
  }
  const int pid = nodePid(options.simulator);
  if (pid <= 0) {
    ROS_FATAL_STREAM("cannot find the PID of " << options.simulator << " (set ~simulator)");
    return 1;
  }

  eval::SoakHooks hooks;
  hooks.resident_mib = [pid] { return eval::residentMiB(pid); };
  hooks.keep_going = [] { return ros::ok(); };
  hooks.on_failure = [](long step, const std::string& what) {
    ROS_ERROR_STREAM("step " << step << ": " << what);
  };
  hooks.on_window = [](const eval::SoakWindow& w) {
    std::printf("%9ld %8llu %9.1f %19.1f\n", w.step, static_cast<unsigned long long>(w.resets),
                w.steps_per_s, w.resident_mib);
    std::fflush(stdout);
  };
  std::printf("    steps   resets   steps/s   simulator RSS MiB\n");
  eval::SoakReport r;
  try {
    r = eval::runSoak(client, options.soak, hooks);
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM("soak on " << client.describe() << ": " << error.what());
    return 1;
  }
  std::printf(
      "summary: %ld steps through the services in %.1f s (%.1f steps/s incl. resets), %d failed; "
      "simulator RSS after warm-up %.2f MiB, at the end %.2f MiB (growth %.2f MiB); rate first "
      "window %.1f/s, last %.1f/s (ratio %.2f)\n",
      r.steps, r.seconds, r.steps / r.seconds, r.failures, r.baseline_mib, r.end_mib, r.growthMiB(),
      r.first_rate, r.last_rate, r.rateRatio());
  const std::vector<std::string> problems = eval::soakProblems(r, options.limits);
  for (const std::string& problem : problems) ROS_ERROR_STREAM("soak check failed: " << problem);
  return problems.empty() ? 0 : 1;
}
