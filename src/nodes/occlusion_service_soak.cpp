// occlusion_service_soak: drives the running simulator through its services for many steps and
// watches the simulator's resident memory and the step rate. Private parameters:
// serviceSoakOptionTable() (ros/service_probe_options.hpp; doc/PARAMETERS.md): with ~check, exits
// 1 when the simulator's memory grew more than ~max_growth_mb after warm-up, the last window's
// rate fell below ~min_rate_ratio of the first's, or a request failed.
// The simulator's PID comes from its ROS slave API (getPid); its memory is read from /proc, so
// both must run on the same machine.
#include <ros/network.h>
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <string>

#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/common/random.hpp"
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

/// Resident set size of process `pid` [MiB]; negative when it cannot be read.
double residentMiB(int pid) {
  std::ifstream statm("/proc/" + std::to_string(pid) + "/statm");
  long pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return -1.0;
  return static_cast<double>(pages_resident) * sysconf(_SC_PAGESIZE) / (1024.0 * 1024.0);
}

using occlusion_env::Reset;
using occlusion_env::Status;
using occlusion_env::Step;
using Clock = std::chrono::steady_clock;

/// One soak: persistent connections to the simulator's services, the scene seeds and the counts.
class Soak {
 public:
  Soak(const occlusion_env::ServiceSoakOptions& options, ros::NodeHandle& node, int pid)
      : options_(options),
        reset_client_(
            node.serviceClient<Reset>(node.resolveName(occlusion_env::names::kResetService), true)),
        step_client_(
            node.serviceClient<Step>(node.resolveName(occlusion_env::names::kStepService), true)),
        pid_(pid) {}

  /// A new episode on the next seed that resets; false when the service fails.
  bool resetNext() {
    for (int tries = 0; tries < 100; ++tries) {
      Reset reset;
      reset.request.seed = seed_++;
      if (!reset_client_.call(reset)) return false;
      if (reset.response.status.code == Status::OK) {
        steps_in_episode_ = 0;
        return true;
      }
    }
    return false;
  }

  enum class Outcome { kStepped, kFailed, kStop };  // kStop: the soak cannot go on

  /// Every step, a line per report window, then the summary; the process's exit code.
  int run() {
    const auto start = Clock::now();
    window_start_ = start;
    baseline_mib_ = residentMiB(pid_);
    std::printf("    steps   resets   steps/s   simulator RSS MiB\n");
    for (int step = 1; step <= options_.steps && ros::ok(); ++step) {
      const Outcome outcome = stepOnce(step);
      if (outcome == Outcome::kStop) break;
      if (outcome == Outcome::kFailed) continue;
      if (step == options_.warmup) baseline_mib_ = residentMiB(pid_);
      if (step % options_.report_every == 0 || step == options_.steps) report(step);
    }
    return summarize(std::chrono::duration<double>(Clock::now() - start).count());
  }

 private:
  // One step in a random direction (and a reset when its episode is over).
  Outcome stepOnce(int step) {
    const double angle = random_.uniform(-M_PI, M_PI);
    Step request;
    request.request.action.d_azimuth = std::cos(angle);
    request.request.action.d_elevation = std::sin(angle);
    if (!step_client_.call(request) || request.response.status.code != Status::OK) {
      ++failures_;
      ROS_ERROR_STREAM("step " << step << " failed: " << request.response.status.message);
      return resetNext() ? Outcome::kFailed : Outcome::kStop;
    }
    ++steps_in_episode_;
    if (request.response.terminated || request.response.truncated ||
        steps_in_episode_ >= options_.reset_every) {
      if (!resetNext()) {
        ++failures_;
        return Outcome::kStop;
      }
    }
    return Outcome::kStepped;
  }

  void report(int step) {
    const auto now = Clock::now();
    const int window =
        step % options_.report_every == 0 ? options_.report_every : step % options_.report_every;
    const double rate = window / std::chrono::duration<double>(now - window_start_).count();
    window_start_ = now;
    if (first_rate_ == 0.0) first_rate_ = rate;
    last_rate_ = rate;
    std::printf("%9d %8llu %9.1f %19.1f\n", step, static_cast<unsigned long long>(seed_), rate,
                residentMiB(pid_));
    std::fflush(stdout);
  }

  int summarize(double seconds) const {
    const double end_mib = residentMiB(pid_);
    const double growth = end_mib - baseline_mib_;
    std::printf(
        "summary: %d steps through the services in %.1f s (%.1f steps/s incl. resets), %d failed; "
        "simulator RSS after warm-up %.2f MiB, at the end %.2f MiB (growth %.2f MiB); rate first "
        "window %.1f/s, last %.1f/s (ratio %.2f)\n",
        options_.steps, seconds, options_.steps / seconds, failures_, baseline_mib_, end_mib,
        growth, first_rate_, last_rate_, last_rate_ / first_rate_);
    if (options_.check && (failures_ > 0 || growth > options_.max_growth_mib ||
                           last_rate_ < options_.min_rate_ratio * first_rate_)) {
      ROS_ERROR("soak check failed (failures, memory growth or rate decay beyond the limits)");
      return 1;
    }
    return 0;
  }

  const occlusion_env::ServiceSoakOptions& options_;
  ros::ServiceClient reset_client_;
  ros::ServiceClient step_client_;
  const int pid_;
  occlusion_env::RandomSource random_{12345};
  std::uint64_t seed_ = 0;
  int steps_in_episode_ = 0;
  int failures_ = 0;
  Clock::time_point window_start_;
  double baseline_mib_ = 0.0, first_rate_ = 0.0, last_rate_ = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  ros::init(argc, argv, "occlusion_service_soak");
  ros::NodeHandle private_node("~");
  ros::NodeHandle node(names::kNamespace);
  warnAboutUnknownParameters(private_node, serviceSoakOptionTable());
  ServiceSoakOptions options;
  try {
    readParameters(private_node, serviceSoakOptionTable(), options);
  } catch (const ParameterError& error) {
    ROS_FATAL_STREAM("occlusion_service_soak: " << error.what());
    return 1;
  }

  // Persistent connections are opened on the first call: create them once the services exist.
  const std::string reset_name = node.resolveName(names::kResetService);
  const std::string step_name = node.resolveName(names::kStepService);
  if (!ros::service::waitForService(reset_name, ros::Duration(60.0)) ||
      !ros::service::waitForService(step_name, ros::Duration(10.0))) {
    ROS_FATAL_STREAM("no simulator: " << reset_name << " did not appear in 60 s");
    return 1;
  }
  const int pid = nodePid(options.simulator);
  if (pid <= 0) {
    ROS_FATAL_STREAM("cannot find the PID of " << options.simulator << " (set ~simulator)");
    return 1;
  }
  Soak soak(options, node, pid);
  if (!soak.resetNext()) {
    ROS_FATAL_STREAM("the first reset failed (" << reset_name << ")");
    return 1;
  }
  return soak.run();
}
