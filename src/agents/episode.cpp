#include "occlusion_env/agents/episode.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

constexpr const char* kHeaderV1 =
    "agent,scene_set,scene_seed,start_azimuth_rad,max_steps,steps,success,final_occlusion_px,"
    "wall_time_s";

constexpr EpisodeEnd kAllEnds[] = {EpisodeEnd::kSuccess,         EpisodeEnd::kTruncated,
                                   EpisodeEnd::kStepLimit,       EpisodeEnd::kEnvironmentError,
                                   EpisodeEnd::kEnvironmentLost, EpisodeEnd::kAgentFailed,
                                   EpisodeEnd::kStopped,         EpisodeEnd::kUnusableView};

void requirePlainName(const std::string& name, const char* what) {
  if (name.empty() || name.find_first_of(",\"\n\r") != std::string::npos) {
    throw InvalidArgumentError(
        std::string("CSV ") + what +
        " must be non-empty without commas, quotes or newlines: " + quoted(name));
  }
}

std::string csvSafe(std::string text) {
  std::replace_if(
      text.begin(), text.end(),
      [](char c) { return c == ',' || c == '"' || c == '\n' || c == '\r' || c == '\0'; }, ' ');
  return text;
}

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, separator)) fields.push_back(field);
  if (!line.empty() && line.back() == separator) fields.emplace_back();
  return fields;
}

std::vector<double> parseAngles(const std::string& text) {
  std::vector<double> angles;
  if (text.empty()) return angles;
  for (const std::string& item : split(text, ';')) angles.push_back(std::stod(item));
  return angles;
}

}  // namespace

const char* toString(EpisodeEnd end) {
  switch (end) {
    case EpisodeEnd::kSuccess:
      return "success";
    case EpisodeEnd::kTruncated:
      return "truncated";
    case EpisodeEnd::kStepLimit:
      return "step_limit";
    case EpisodeEnd::kEnvironmentError:
      return "environment_error";
    case EpisodeEnd::kEnvironmentLost:
      return "environment_lost";
    case EpisodeEnd::kAgentFailed:
      return "agent_failed";
    case EpisodeEnd::kStopped:
      return "stopped";
    case EpisodeEnd::kUnusableView:
      return "unusable_view";
  }
  return "unknown";
}

EpisodeEnd parseEpisodeEnd(const std::string& text) {
  for (const EpisodeEnd end : kAllEnds) {
    if (text == toString(end)) return end;
  }
  throw InvalidArgumentError("unknown episode end " + quoted(text));
}

std::string episodeCsvHeader() {
  return std::string("version,") + kHeaderV1 + ",end,message,azimuths_rad,elevations_rad";
}

void writeEpisodeCsvRow(std::ostream& out, const EpisodeRecord& record) {
  requirePlainName(record.agent, "agent name");
  requirePlainName(record.scene_set, "scene set name");
  std::ostringstream row;
  row << kEpisodeCsvVersion << ',' << std::setprecision(17) << record.agent << ','
      << record.scene_set << ',' << record.scene_seed << ',' << record.start_azimuth_rad << ','
      << record.max_steps << ',' << record.steps << ',' << (record.success() ? 1 : 0) << ','
      << record.final_occlusion_px << ',' << std::setprecision(6) << record.wall_time_s << ','
      << toString(record.end) << ',' << csvSafe(record.message) << ',' << std::setprecision(17);
  for (std::size_t i = 0; i < record.path.size(); ++i) {
    row << (i ? ";" : "") << record.path[i].azimuth_rad;
  }
  row << ',';
  for (std::size_t i = 0; i < record.path.size(); ++i) {
    row << (i ? ";" : "") << record.path[i].elevation_rad;
  }
  row << '\n';
  out << row.str();
}

std::vector<EpisodeRecord> readEpisodeCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidArgumentError("cannot read episode CSV " + path);
  std::string line;
  if (!std::getline(in, line)) throw InvalidArgumentError(path + ": empty file");
  int version = 0;
  if (line == episodeCsvHeader()) {
    version = 2;
  } else if (line == kHeaderV1) {
    version = 1;
  } else {
    throw InvalidArgumentError(path + ": line 1 is not an episode CSV header (version 2: '" +
                               episodeCsvHeader() + "')");
  }
  const std::size_t columns = split(line, ',').size();
  std::vector<EpisodeRecord> records;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    const std::vector<std::string> all = split(line, ',');
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    if (all.size() != columns) {
      throw InvalidArgumentError(where + "expected " + std::to_string(columns) + " columns, got " +
                                 std::to_string(all.size()));
    }
    // fields[0..8] are the version 1 columns in both versions.
    const std::vector<std::string> fields(all.begin() + (version == 2 ? 1 : 0), all.end());
    EpisodeRecord record;
    try {
      if (version == 2 && all[0] != "2") throw std::invalid_argument("version is not 2");
      record.agent = fields[0];
      record.scene_set = fields[1];
      std::size_t used = 0;
      record.scene_seed = std::stoull(fields[2], &used);
      if (used != fields[2].size() || fields[2][0] == '-') {
        throw std::invalid_argument("scene_seed");
      }
      record.start_azimuth_rad = std::stod(fields[3]);
      record.max_steps = std::stoi(fields[4]);
      record.steps = std::stoi(fields[5]);
      if (fields[6] != "0" && fields[6] != "1") throw std::invalid_argument("success not 0/1");
      record.final_occlusion_px = std::llround(std::stod(fields[7]));
      record.wall_time_s = std::stod(fields[8]);
      if (version == 1) {
        record.end = fields[6] == "1" ? EpisodeEnd::kSuccess : EpisodeEnd::kStepLimit;
      } else {
        record.end = parseEpisodeEnd(fields[9]);
        record.message = fields[10];
        const std::vector<double> azimuths = parseAngles(fields[11]);
        const std::vector<double> elevations = parseAngles(fields[12]);
        if (azimuths.size() != elevations.size()) {
          throw std::invalid_argument("azimuths and elevations differ in length");
        }
        for (std::size_t i = 0; i < azimuths.size(); ++i) {
          record.path.push_back({azimuths[i], elevations[i]});
        }
        if (record.success() != (fields[6] == "1")) {
          throw std::invalid_argument("success and end disagree");
        }
      }
    } catch (const std::exception& error) {
      throw InvalidArgumentError(where + "bad value (" + error.what() + ")");
    }
    if (record.agent.empty() || record.steps < 0 || record.max_steps < 1) {
      throw InvalidArgumentError(where + "empty agent or negative steps or max_steps < 1");
    }
    records.push_back(std::move(record));
  }
  return records;
}

EpisodeStatistics summarizeEpisodes(const std::vector<EpisodeRecord>& records) {
  EpisodeStatistics stats;
  stats.episodes = static_cast<int>(records.size());
  double sum = 0.0, wall_time_s = 0.0;
  for (const EpisodeRecord& record : records) {
    if (!record.completed()) continue;
    ++stats.completed;
    stats.successes += record.success() ? 1 : 0;
    stats.max_steps = std::max(stats.max_steps, record.max_steps);
    sum += record.countedSteps();
    wall_time_s += record.wall_time_s;
  }
  if (stats.completed == 0) {
    stats.mean_steps = stats.sd_steps = std::numeric_limits<double>::quiet_NaN();
    return stats;
  }
  stats.mean_steps = sum / stats.completed;
  stats.mean_wall_time_s = wall_time_s / stats.completed;
  double squares = 0.0;
  for (const EpisodeRecord& record : records) {
    if (!record.completed()) continue;
    const double d = record.countedSteps() - stats.mean_steps;
    squares += d * d;
  }
  stats.sd_steps = stats.completed > 1 ? std::sqrt(squares / (stats.completed - 1))
                                       : std::numeric_limits<double>::quiet_NaN();
  return stats;
}

}  // namespace occlusion_env
