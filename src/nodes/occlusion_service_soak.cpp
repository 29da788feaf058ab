// occlusion_service_soak: drives the running simulator through its services for many steps and
// watches the simulator's resident memory and the step rate. Private parameters:
//   ~steps (20000), ~reset_every (50), ~report_every (2000), ~warmup (1000) steps;
//   ~check (false): exit 1 when the simulator's memory grew more than ~max_growth_mb (5) after
//   warm-up, the last window's rate fell below ~min_rate_ratio (0.7) of the first's, or a request
//   failed; ~simulator: the simulator node's name (default /occlusion_sim).
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

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  ros::init(argc, argv, "occlusion_service_soak");
  ros::NodeHandle private_node("~");
  ros::NodeHandle node(names::kNamespace);
  const int total_steps = private_node.param("steps", 20000);
  const int reset_every = std::max(1, private_node.param("reset_every", 50));
  const int report_every = std::max(1, private_node.param("report_every", 2000));
  const int warmup = private_node.param("warmup", 1000);
  const bool check = private_node.param("check", false);
  const double max_growth_mib = private_node.param("max_growth_mb", 5.0);
  const double min_rate_ratio = private_node.param("min_rate_ratio", 0.7);
  const std::string simulator =
      private_node.param<std::string>("simulator", std::string("/") + names::kSimulatorNode);

  // Persistent connections are opened on the first call: create them once the services exist.
  const std::string reset_name = node.resolveName(names::kResetService);
  const std::string step_name = node.resolveName(names::kStepService);
  if (!ros::service::waitForService(reset_name, ros::Duration(60.0)) ||
      !ros::service::waitForService(step_name, ros::Duration(10.0))) {
    ROS_FATAL_STREAM("no simulator: " << reset_name << " did not appear in 60 s");
    return 1;
  }
  ros::ServiceClient reset_client = node.serviceClient<Reset>(reset_name, true);
  ros::ServiceClient step_client = node.serviceClient<Step>(step_name, true);
  const int pid = nodePid(simulator);
  if (pid <= 0) {
    ROS_FATAL_STREAM("cannot find the PID of " << simulator << " (set ~simulator)");
    return 1;
  }

  std::uint64_t seed = 0;
  int steps_in_episode = 0, failures = 0;
  const auto resetNext = [&]() -> bool {
    for (int tries = 0; tries < 100; ++tries) {
      Reset reset;
      reset.request.seed = seed++;
      if (!reset_client.call(reset)) return false;
      if (reset.response.status.code == Status::OK) {
        steps_in_episode = 0;
        return true;
      }
    }
    return false;
  };
  if (!resetNext()) {
    ROS_FATAL_STREAM("the first reset failed (" << reset_name << ")");
    return 1;
  }

  using Clock = std::chrono::steady_clock;
  RandomSource random(12345);
  const auto start = Clock::now();
  auto window_start = start;
  double baseline_mib = residentMiB(pid), first_rate = 0.0, last_rate = 0.0;
  std::printf("    steps   resets   steps/s   simulator RSS MiB\n");
  for (int step = 1; step <= total_steps && ros::ok(); ++step) {
    const double angle = random.uniform(-M_PI, M_PI);
    Step request;
    request.request.action.d_azimuth = std::cos(angle);
    request.request.action.d_elevation = std::sin(angle);
    if (!step_client.call(request) || request.response.status.code != Status::OK) {
      ++failures;
      ROS_ERROR_STREAM("step " << step << " failed: " << request.response.status.message);
      if (!resetNext()) break;
      continue;
    }
    ++steps_in_episode;
    if (request.response.terminated || request.response.truncated ||
        steps_in_episode >= reset_every) {
      if (!resetNext()) {
        ++failures;
        break;
      }
    }
    if (step == warmup) baseline_mib = residentMiB(pid);
    if (step % report_every == 0 || step == total_steps) {
      const auto now = Clock::now();
      const int window = step % report_every == 0 ? report_every : step % report_every;
      const double rate = window / std::chrono::duration<double>(now - window_start).count();
      window_start = now;
      if (first_rate == 0.0) first_rate = rate;
      last_rate = rate;
      std::printf("%9d %8llu %9.1f %19.1f\n", step, static_cast<unsigned long long>(seed), rate,
                  residentMiB(pid));
      std::fflush(stdout);
    }
  }
  const double end_mib = residentMiB(pid);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double growth = end_mib - baseline_mib;
  std::printf(
      "summary: %d steps through the services in %.1f s (%.1f steps/s incl. resets), %d failed; "
      "simulator RSS after warm-up %.2f MiB, at the end %.2f MiB (growth %.2f MiB); rate first "
      "window %.1f/s, last %.1f/s (ratio %.2f)\n",
      total_steps, seconds, total_steps / seconds, failures, baseline_mib, end_mib, growth,
      first_rate, last_rate, last_rate / first_rate);
  if (check &&
      (failures > 0 || growth > max_growth_mib || last_rate < min_rate_ratio * first_rate)) {
    ROS_ERROR("soak check failed (failures, memory growth or rate decay beyond the limits)");
    return 1;
  }
  return 0;
}
