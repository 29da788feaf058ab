#include "occlusion_env/ros/agent_node.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "occlusion_env/eval/scene_set.hpp"
#include "occlusion_env/ros/msg_conversion.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxEpisodes = 1'000'000;
constexpr int kResetAttempts = 3;  // transport failures of one reset before the episode fails

// CSV cells must not hold the separator, quotes or line breaks.
std::string csvSafe(std::string text) {
  std::replace_if(
      text.begin(), text.end(),
      [](char c) { return c == ',' || c == '"' || c == '\n' || c == '\r'; }, ' ');
  return text;
}

std::string seconds(double value) {
  std::ostringstream text;
  text << value << " s";
  return text.str();
}

std::string joinedAngles(const std::vector<double>& angles) {
  std::ostringstream text;
  text << std::setprecision(9);
  for (std::size_t i = 0; i < angles.size(); ++i) text << (i ? ";" : "") << angles[i];
  return text.str();
}

}  // namespace

const std::vector<std::string>& agentNodeAgents() {
  static const std::vector<std::string> kAgents = {"random", "gradient"};
  return kAgents;
}

AgentNodeOptions readAgentNodeOptions(const ros::NodeHandle& private_node,
                                      const std::string& agent) {
  const ParameterReader reader(private_node);
  AgentNodeOptions options;
  options.agent = agent;
  reader.read("max_steps", options.max_steps);
  reader.read("csv", options.csv_path);
  if (!options.csv_path.empty() && fs::path(options.csv_path).is_relative()) {
    // Relative to ROS_HOME, as ROS puts its own files, whatever the working directory.
    const char* ros_home = std::getenv("ROS_HOME");
    const char* home = std::getenv("HOME");
    const fs::path base = ros_home != nullptr && *ros_home != '\0'
                              ? fs::path(ros_home)
                              : fs::path(home != nullptr ? home : ".") / ".ros";
    options.csv_path = (base / options.csv_path).string();
  }
  reader.read("service_timeout", options.service_timeout_s);
  reader.read("step_rate", options.step_rate_hz);
  reader.read("preset", options.preset);
  reader.read("categories", options.categories);
  if (private_node.hasParam("start_azimuth")) {
    options.set_start_azimuth = true;
    reader.read("start_azimuth", options.start_azimuth_rad);
  }
  if (private_node.hasParam("start_elevation")) {
    options.set_start_elevation = true;
    reader.read("start_elevation", options.start_elevation_rad);
  }

  std::string scene_set_path;
  reader.read("scene_set", scene_set_path);
  reader.read("seeds", options.seeds);
  if (options.seeds.empty() && !scene_set_path.empty()) {
    eval::SceneSet set;
    try {
      set = eval::loadSceneSet(scene_set_path);
    } catch (const std::exception& error) {
      throw ParameterError(reader.prefix("scene_set") + ": " + error.what());
    }
    options.seeds = set.seeds;
    options.scene_set_name = set.name;
    options.preset = set.preset;
    options.categories = set.categories;
    options.set_start_azimuth = options.set_start_elevation = true;
    options.start_azimuth_rad = set.start_azimuth_rad;
    options.start_elevation_rad = set.start_elevation_rad;
    ROS_INFO_STREAM("scene set " << set.name << " (" << set.seeds.size()
                                 << " seeds): run the simulator with catalog_source " << set.source
                                 << " and num_objects " << set.num_objects << " to get its scenes");
  }
  if (options.seeds.empty()) {
    std::int64_t first_seed = 0;
    int episodes = 10;
    reader.read("seed", first_seed);
    reader.read("episodes", episodes);
    if (first_seed < 0) throw ParameterError(reader.prefix("seed") + " must be >= 0");
    if (episodes < 1 || episodes > kMaxEpisodes) {
      throw ParameterError(reader.prefix("episodes") + " must be in [1, " +
                           std::to_string(kMaxEpisodes) + "]");
    }
    for (int i = 0; i < episodes; ++i) options.seeds.push_back(first_seed + i);
  }

  if (std::find(agentNodeAgents().begin(), agentNodeAgents().end(), agent) ==
      agentNodeAgents().end()) {
    throw ParameterError("unknown agent '" + agent + "' (random or gradient)");
  }
  if (options.max_steps < 1) throw ParameterError(reader.prefix("max_steps") + " must be >= 1");
  if (options.service_timeout_s < 0.0) {
    throw ParameterError(reader.prefix("service_timeout") + " must be >= 0 (0 waits forever)");
  }
  if (options.step_rate_hz < 0.0) {
    throw ParameterError(reader.prefix("step_rate") + " must be >= 0 (0: no limit)");
  }
  for (double angle : {options.start_azimuth_rad, options.start_elevation_rad}) {
    if (!std::isfinite(angle)) throw ParameterError("start_azimuth/start_elevation must be finite");
  }
  return options;
}

AgentNode::AgentNode(const AgentNodeOptions& options, ros::NodeHandle node,
                     ros::NodeHandle private_node)
    : options_(options), node_(std::move(node)), private_node_(std::move(private_node)) {
  if (options_.agent == "random") {
    agent_ = std::make_unique<RandomAgent>();
  } else if (options_.agent == "gradient") {
    needs_gradient_ = true;
    agent_ = std::make_unique<GradientAgent>([this] { return requestGradient(); });
  } else {
    throw ParameterError("unknown agent '" + options_.agent + "' (random or gradient)");
  }
  episodes_publisher_ = private_node_.advertise<EpisodeReport>(names::kEpisodesTopic, 100);
  if (!options_.csv_path.empty()) {
    const fs::path path(options_.csv_path);
    if (path.has_parent_path()) {
      std::error_code error;
      fs::create_directories(path.parent_path(), error);
    }
    csv_.open(options_.csv_path);
    if (!csv_) throw ParameterError("parameter ~csv: cannot write " + options_.csv_path);
    // The first nine columns are occlusion_eval's episode CSV (occlusion_eval --summarize).
    csv_ << "agent,scene_set,scene_seed,start_azimuth_rad,max_steps,steps,success,"
            "final_occlusion_px,wall_time_s,completed,message,azimuths_rad,elevations_rad\n";
    csv_.flush();
  }
}

void AgentNode::connect() {
  const std::string reset_name = node_.resolveName(names::kResetService);
  const std::string step_name = node_.resolveName(names::kStepService);
  const double timeout_s = options_.service_timeout_s;
  const ros::Duration timeout = timeout_s > 0.0 ? ros::Duration(timeout_s) : ros::Duration(-1);
  ROS_INFO_STREAM(
      "waiting for " << reset_name << " and " << step_name
                     << (timeout_s > 0.0 ? " (up to " + seconds(timeout_s) + ")" : std::string()));
  if (!ros::service::waitForService(reset_name, timeout) ||
      !ros::service::waitForService(step_name, timeout)) {
    throw SimulatorUnavailableError("the simulator's services " + reset_name + " and " + step_name +
                                    " did not appear within " + seconds(timeout_s));
  }
  // Fresh persistent clients: those of a simulator that went away cannot be reused.
  reset_client_ = node_.serviceClient<Reset>(reset_name, /*persistent=*/true);
  step_client_ = node_.serviceClient<Step>(step_name, /*persistent=*/true);
  if (needs_gradient_) {
    const std::string gradient_name = node_.resolveName(names::kGradientService);
    // The reset and step services are up, so the node serving them is up: a short wait suffices.
    if (!ros::service::waitForService(gradient_name, ros::Duration(2.0))) {
      throw ParameterError("the " + options_.agent + " agent needs " + gradient_name +
                           " (occlusion_env/GetOcclusionGradient), which only the simulator "
                           "offers; the node serving " +
                           reset_name +
                           " has none (a real camera?). Use an agent that needs only images, "
                           "e.g. random_agent.");
    }
    gradient_client_ =
        node_.serviceClient<GetOcclusionGradient>(gradient_name, /*persistent=*/true);
  }
}

GradientResult AgentNode::requestGradient() {
  gradient_call_.request.method = GetOcclusionGradient::Request::DEFAULT;
  if (!gradient_client_.call(gradient_call_)) {
    throw SimulatorUnavailableError("the call to " + gradient_client_.getService() + " failed");
  }
  const GetOcclusionGradient::Response& response = gradient_call_.response;
  GradientResult result;
  if (response.status.code != Status::OK) {
    result.reason = "gradient refused: " + response.status.message;
    ROS_WARN_STREAM_THROTTLE(5.0, result.reason);
    return result;
  }
  result.loss = response.loss;
  result.gradient = {response.d_azimuth, response.d_elevation};
  result.valid = response.valid && result.gradient.allFinite();
  result.reason = response.reason;
  if (!result.valid) result.gradient.setZero();
  return result;
}

EpisodeReport AgentNode::runEpisode(int index, std::uint64_t seed) {
  const auto start = std::chrono::steady_clock::now();
  EpisodeReport report;
  report.agent = options_.agent;
  report.episode_index = index;
  report.seed = seed;
  report.max_steps = options_.max_steps;
  report.final_occlusion_pixels = -1;
  Observation observation;
  StepInfo info;
  try {
    Reset::Request& reset = reset_call_.request;
    reset.seed = seed;
    reset.preset = options_.preset;
    reset.categories = options_.categories;
    reset.set_start_azimuth = options_.set_start_azimuth;
    reset.start_azimuth = options_.start_azimuth_rad;
    reset.set_start_elevation = options_.set_start_elevation;
    reset.start_elevation = options_.start_elevation_rad;
    // Nothing of the episode is lost when a reset fails in transit (e.g. to a simulator still
    // shutting down after a crash): reconnect and try again, a few times.
    for (int attempt = 1; !reset_client_.call(reset_call_); ++attempt) {
      if (attempt == kResetAttempts || !ros::ok()) {
        throw SimulatorUnavailableError("the call to " + reset_client_.getService() + " failed " +
                                        std::to_string(attempt) + " times");
      }
      ROS_WARN_STREAM("the call to " << reset_client_.getService()
                                     << " failed; reconnecting and trying again");
      ros::WallDuration(0.2).sleep();
      connect();
    }
    if (reset_call_.response.status.code != Status::OK) {
      report.message = "reset refused: " + reset_call_.response.status.message;
    } else {
      agent_->reset(seed);
      const CameraObservation* latest = &reset_call_.response.observation;
      report.azimuths.push_back(latest->azimuth);
      report.elevations.push_back(latest->elevation);
      report.final_occlusion_pixels = latest->occlusion.total_pixels;
      bool over = false;
      std::unique_ptr<ros::WallRate> rate;
      if (options_.step_rate_hz > 0.0)
        rate = std::make_unique<ros::WallRate>(options_.step_rate_hz);
      while (!over && report.steps < options_.max_steps && ros::ok()) {
        if (rate) rate->sleep();
        viewObservation(*latest, observation, info);
        const Action action = agent_->act(observation, info);
        step_call_.request.action.d_azimuth = action.d_azimuth_rad;
        step_call_.request.action.d_elevation = action.d_elevation_rad;
        if (!step_client_.call(step_call_)) {
          throw SimulatorUnavailableError("the call to " + step_client_.getService() +
                                          " failed at step " + std::to_string(report.steps + 1));
        }
        const Step::Response& response = step_call_.response;
        if (response.status.code != Status::OK) {
          report.message =
              "step " + std::to_string(report.steps + 1) + " refused: " + response.status.message;
          break;
        }
        latest = &response.observation;
        ++report.steps;
        report.azimuths.push_back(latest->azimuth);
        report.elevations.push_back(latest->elevation);
        report.final_occlusion_pixels = response.occlusion_pixels;
        report.success = response.terminated;
        over = response.terminated || response.truncated;
      }
      if (report.message.empty()) {
        report.completed = over || report.steps == options_.max_steps;
        if (!report.completed) report.message = "interrupted (node shutting down)";
      }
    }
  } catch (const SimulatorUnavailableError& error) {
    report.message = std::string("lost the simulator: ") + error.what();
  }
  report.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.header.stamp = ros::Time::now();
  return report;
}

void AgentNode::writeCsvRow(const EpisodeReport& report) {
  if (!csv_.is_open()) return;
  csv_ << std::setprecision(9) << report.agent << ',' << csvSafe(options_.scene_set_name) << ','
       << report.seed << ',' << (report.azimuths.empty() ? 0.0 : report.azimuths.front()) << ','
       << report.max_steps << ',' << report.steps << ',' << (report.success ? 1 : 0) << ','
       << report.final_occlusion_pixels << ',' << report.wall_time << ','
       << (report.completed ? 1 : 0) << ',' << csvSafe(report.message) << ','
       << joinedAngles(report.azimuths) << ',' << joinedAngles(report.elevations) << '\n';
  csv_.flush();
}

int AgentNode::run() {
  connect();
  const int total = static_cast<int>(options_.seeds.size());
  ROS_INFO_STREAM(
      options_.agent << " agent: " << total << " episodes, at most " << options_.max_steps
                     << " steps each"
                     << (options_.csv_path.empty() ? std::string() : ", CSV " + options_.csv_path));
  int completed = 0;
  for (int index = 0; index < total && ros::ok(); ++index) {
    const EpisodeReport report = runEpisode(index, options_.seeds[index]);
    reports_.push_back(report);
    episodes_publisher_.publish(report);
    writeCsvRow(report);
    std::ostringstream line;
    line << "episode " << index + 1 << "/" << total << " seed " << report.seed << ": ";
    if (report.completed) {
      ++completed;
      line << (report.success ? "unoccluded after " : "still occluded after ") << report.steps
           << (report.steps == 1 ? " step" : " steps") << ", final occlusion "
           << report.final_occlusion_pixels << " px (" << std::fixed << std::setprecision(2)
           << report.wall_time << " s)";
      ROS_INFO_STREAM(line.str());
    } else {
      line << "FAILED after " << report.steps << " steps: " << report.message;
      ROS_ERROR_STREAM(line.str());
      if (!ros::ok()) break;
      if (report.message.rfind("lost the simulator", 0) == 0) {
        ROS_WARN_STREAM("waiting for the simulator to return, then going on with episode "
                        << index + 2);
        connect();
      }
    }
  }
  logSummary();
  // Publishing is asynchronous: give the last reports time to leave before the node exits.
  if (episodes_publisher_.getNumSubscribers() > 0) ros::WallDuration(0.5).sleep();
  return completed;
}

void AgentNode::logSummary() const {
  int completed = 0, successes = 0;
  double sum = 0.0, sum_squares = 0.0;
  for (const EpisodeReport& report : reports_) {
    if (!report.completed) continue;
    ++completed;
    successes += report.success ? 1 : 0;
    const double counted = report.success ? report.steps : report.max_steps;
    sum += counted;
    sum_squares += counted * counted;
  }
  if (completed == 0) {
    ROS_WARN_STREAM(options_.agent << " agent: no episode completed");
    return;
  }
  const double mean = sum / completed;
  const double sd =
      completed > 1
          ? std::sqrt(std::max(0.0, (sum_squares - completed * mean * mean) / (completed - 1)))
          : 0.0;
  ROS_INFO_STREAM(options_.agent << " agent done: " << successes << "/" << completed
                                 << " completed episodes unoccluded, steps " << std::fixed
                                 << std::setprecision(1) << mean << " +/- " << sd
                                 << " (failures counted as " << options_.max_steps << "); "
                                 << reports_.size() - completed << " cut short");
}

const std::vector<std::string>& agentNodeParameterNames() {
  static const std::vector<std::string> kNames = {
      "seeds",           "scene_set", "seed",       "episodes", "max_steps",       "start_azimuth",
      "start_elevation", "preset",    "categories", "csv",      "service_timeout", "step_rate"};
  return kNames;
}

int runAgentNodeMain(int argc, char** argv, const std::string& agent) {
  ros::init(argc, argv, agent + "_agent");
  ros::NodeHandle private_node("~");
  ros::NodeHandle node(names::kNamespace);
  for (const std::string& name : unknownParameters(private_node, agentNodeParameterNames())) {
    ROS_WARN_STREAM("unknown parameter " << private_node.resolveName(name) << " is ignored");
  }
  try {
    AgentNode agent_node(readAgentNodeOptions(private_node, agent), node, private_node);
    agent_node.run();
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM(agent << "_agent: " << error.what());
    return 1;
  }
  return 0;
}

}  // namespace occlusion_env
