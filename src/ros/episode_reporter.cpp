#include "occlusion_env/ros/episode_reporter.hpp"

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "occlusion_env/EpisodeReport.h"
#include "occlusion_env/ros/msg_conversion.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {

EpisodeReporter::EpisodeReporter(ros::NodeHandle& private_node, const std::string& csv_path) {
  publisher_ = private_node.advertise<EpisodeReport>(names::kEpisodesTopic, 100);
  if (csv_path.empty()) return;
  const std::filesystem::path path(csv_path);
  if (path.has_parent_path()) {
    std::error_code error;
    std::filesystem::create_directories(path.parent_path(), error);
  }
  csv_.open(csv_path);
  if (!csv_) throw ParameterError("parameter ~csv: cannot write " + csv_path);
  csv_ << episodeCsvHeader() << '\n';
  csv_.flush();
}

void EpisodeReporter::report(const EpisodeRecord& record, int index, int total) {
  records_.push_back(record);
  publisher_.publish(toEpisodeReport(record, index, ros::Time::now()));
  if (csv_.is_open()) {
    writeEpisodeCsvRow(csv_, record);
    csv_.flush();
  }
  std::ostringstream line;
  line << "episode " << index + 1 << "/" << total << " seed " << record.scene_seed << ": ";
  if (record.completed()) {
    // Behind a real camera the end and the occlusion are an estimate, or unknown: say so.
    const bool estimated = record.occlusion_source == OcclusionSource::kEstimated;
    if (record.occlusion_source == OcclusionSource::kUnavailable) {
      line << (record.success() ? "ended after " : "still unknown after ");
    } else {
      line << (estimated ? "estimated " : "")
           << (record.success() ? "unoccluded after " : "still occluded after ");
    }
    line << record.steps << (record.steps == 1 ? " step" : " steps");
    if (record.occlusion_source != OcclusionSource::kUnavailable) {
      line << ", " << (estimated ? "estimated " : "") << "final occlusion "
           << record.final_occlusion_px << " px";
    }
    line << " (" << std::fixed << std::setprecision(2) << record.wall_time_s << " s)";
    ROS_INFO_STREAM(line.str());
  } else {
    line << "CUT SHORT after " << record.steps << " steps (" << toString(record.end)
         << "): " << record.message;
    ROS_ERROR_STREAM(line.str());
  }
}

void EpisodeReporter::finish(const std::string& agent) {
  const EpisodeStatistics stats = summarizeEpisodes(records_);
  if (stats.completed == 0) {
    ROS_WARN_STREAM(agent << " agent: no episode completed");
  } else {
    const bool estimated =
        std::any_of(records_.begin(), records_.end(), [](const EpisodeRecord& record) {
          return record.occlusion_source != OcclusionSource::kGroundTruth;
        });
    ROS_INFO_STREAM(agent << " agent done: " << stats.successes << "/" << stats.completed
                          << " completed episodes unoccluded" << (estimated ? " (estimated)" : "")
                          << ", steps " << std::fixed << std::setprecision(1) << stats.mean_steps
                          << " +/- " << (stats.completed > 1 ? stats.sd_steps : 0.0)
                          << " (failures counted as " << stats.max_steps << "); "
                          << stats.episodes - stats.completed << " cut short");
  }
  // Publishing is asynchronous: give the last reports time to leave before the node exits.
  if (publisher_.getNumSubscribers() > 0) ros::WallDuration(0.5).sleep();
}

}  // namespace occlusion_env
