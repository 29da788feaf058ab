// Where an agent node's episodes go: a log line each, the ~episodes topic (EpisodeReport), a CSV
// row (the core's episode CSV) and a summary line at the end.
#pragma once

#include <ros/ros.h>

#include <fstream>
#include <string>
#include <vector>

#include "occlusion_env/agents/episode.hpp"

namespace occlusion_env {

class EpisodeReporter {
 public:
  /// Advertises ~episodes on `private_node`; opens `csv_path` unless empty (creating its folder).
  /// Throws ParameterError when the CSV cannot be written.
  EpisodeReporter(ros::NodeHandle& private_node, const std::string& csv_path);

  /// Logs, publishes and writes episode `index` (0-based) of `total`.
  void report(const EpisodeRecord& record, int index, int total);
  /// The summary line of the episodes reported so far; waits briefly for the last messages to
  /// leave when someone listens.
  void finish(const std::string& agent);

  const std::vector<EpisodeRecord>& records() const { return records_; }

 private:
  ros::Publisher publisher_;
  std::ofstream csv_;
  std::vector<EpisodeRecord> records_;
};

}  // namespace occlusion_env
