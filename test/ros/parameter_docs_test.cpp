// doc/PARAMETERS.md shows every node's parameter table as its OptionTable writes it, and every
// parameter the launch files and rostests set is one the node declares. After changing a table,
// rewrite the doc's tables with
//   UPDATE_DOCS=1 .build_ws/devel/lib/occlusion_env/ros_unit_tests --gtest_filter='ParameterDocs*'
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "occlusion_env/ros/agent_node_options.hpp"
#include "occlusion_env/ros/camera_bridge.hpp"
#include "occlusion_env/ros/parameters.hpp"
#include "occlusion_env/ros/service_probe_options.hpp"

namespace occlusion_env {
namespace {

namespace fs = std::filesystem;

const std::string kSourceDir = OCCLUSION_ENV_SOURCE_DIR;
const std::string kDocPath = kSourceDir + "/doc/PARAMETERS.md";

struct NodeTable {
  std::string markdown;           // OptionTable::markdown() of the defaults
  std::vector<std::string> keys;  // the parameter names
};

// Each node's table by the node's executable (test_agent_node: occlusion_agent's own main).
std::map<std::string, NodeTable> nodeTables() {
  const auto entry = [](const auto& table) { return NodeTable{table.markdown(), table.keys()}; };
  return {{"occlusion_sim", entry(simulatorOptionTable())},
          {"occlusion_agent", entry(agentNodeOptionTable())},
          {"occlusion_camera_bridge", entry(cameraBridgeOptionTable())},
          {"occlusion_service_bench", entry(serviceBenchOptionTable())},
          {"occlusion_service_soak", entry(serviceSoakOptionTable())}};
}

std::string readText(const std::string& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// `doc` with the text between each "<!-- options-table: NAME -->" line and the next
// "<!-- /options-table -->" replaced by NAME's table; `missing` gets the names without markers.
std::string withTables(const std::string& doc, const std::map<std::string, NodeTable>& tables,
                       std::vector<std::string>& missing) {
  std::string result = doc;
  for (const auto& [name, table] : tables) {
    const std::string open = "<!-- options-table: " + name + " -->\n";
    const std::size_t start = result.find(open);
    const std::size_t end = result.find("<!-- /options-table -->", start);
    if (start == std::string::npos || end == std::string::npos) {
      missing.push_back(name);
      continue;
    }
    result.replace(start + open.size(), end - start - open.size(), table.markdown);
  }
  return result;
}

TEST(ParameterDocs, ParametersMdShowsEveryNodesTable) {
  const std::string doc = readText(kDocPath);
  ASSERT_FALSE(doc.empty()) << kDocPath;
  std::vector<std::string> missing;
  const std::string updated = withTables(doc, nodeTables(), missing);
  EXPECT_TRUE(missing.empty()) << kDocPath << " has no table of " << missing.front();
  const char* update = std::getenv("UPDATE_DOCS");
  if (update != nullptr && std::string(update) == "1") {
    std::ofstream(kDocPath) << updated;
    return;
  }
  if (doc == updated) return;
  std::istringstream stated(doc), generated(updated);
  std::string stated_line, generated_line;
  while (std::getline(stated, stated_line) && std::getline(generated, generated_line) &&
         stated_line == generated_line) {
  }
  ADD_FAILURE() << kDocPath << " differs from the option tables:\n  doc:   " << stated_line
                << "\n  table: " << generated_line
                << "\nrewrite it with UPDATE_DOCS=1 ros_unit_tests --gtest_filter='ParameterDocs*'";
}

// The parameters set in the <node type="TYPE"> elements of a launch file: type -> names.
std::multimap<std::string, std::string> nodeParameters(const std::string& launch) {
  static const std::regex node(R"(<node\b([^>]*?)(/>|>([\s\S]*?)</node>))");
  static const std::regex type(R"(\btype="([^"]+)\")");
  static const std::regex param(R"(<(?:param\b[^>]*?\bname|rosparam\b[^>]*?\bparam)="([^"]+)\")");
  std::multimap<std::string, std::string> parameters;
  for (std::sregex_iterator it(launch.begin(), launch.end(), node), end; it != end; ++it) {
    std::smatch node_type;
    const std::string attributes = (*it)[1].str();
    if (!std::regex_search(attributes, node_type, type)) continue;
    const std::string body = (*it)[3].str();
    for (std::sregex_iterator p(body.begin(), body.end(), param); p != end; ++p) {
      parameters.emplace(node_type[1].str(), (*p)[1].str());
    }
  }
  return parameters;
}

TEST(ParameterDocs, LaunchFilesSetOnlyDeclaredParameters) {
  std::map<std::string, NodeTable> tables = nodeTables();
  tables["test_agent_node"] = tables["occlusion_agent"];
  int checked = 0;
  for (const std::string dir : {"/launch", "/test/ros"}) {
    for (const fs::directory_entry& file : fs::directory_iterator(kSourceDir + dir)) {
      const std::string extension = file.path().extension().string();
      if (extension != ".launch" && extension != ".test") continue;
      for (const auto& [node_type, name] : nodeParameters(readText(file.path().string()))) {
        const auto table = tables.find(node_type);
        if (table == tables.end()) continue;
        const std::vector<std::string>& keys = table->second.keys;
        EXPECT_NE(std::find(keys.begin(), keys.end(), name), keys.end())
            << file.path().filename() << ": " << node_type << " has no parameter " << name;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 50);  // the scan found the launch files' parameters
}

TEST(ParameterDocs, TheLaunchScanFindsParametersAndRosparams) {
  const auto found = nodeParameters(
      "<node pkg=\"p\" type=\"occlusion_sim\" name=\"s\">\n  <param name=\"width\" value=\"1\"/>\n"
      "  <rosparam command=\"load\" file=\"f\"/>\n  <rosparam param=\"categories\">[a]</rosparam>\n"
      "  <param if=\"$(arg x)\" name=\"mode\" value=\"camera\"/>\n</node>\n"
      "<node pkg=\"rviz\" type=\"rviz\" name=\"rviz\"/>\n<test><param name=\"episodes\"/></test>");
  const std::multimap<std::string, std::string> expected = {
      {"occlusion_sim", "width"}, {"occlusion_sim", "categories"}, {"occlusion_sim", "mode"}};
  EXPECT_EQ(found, expected);
}

}  // namespace
}  // namespace occlusion_env
