// The check's contact sheet (learning/check_montage.hpp): which frames, what colours, where.
#include "occlusion_env/learning/check_montage.hpp"

#include <gtest/gtest.h>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace learning {
namespace {

// A network input of S x S px whose RGB is grey (the input's 0 is a level of 0.5) and whose
// depth channel is `depth_unit` (0 near, 1 the far), as network_input.hpp normalises.
torch::Tensor greyInput(int size, double depth_unit) {
  torch::Tensor input = torch::zeros({4, size, size});
  input[3].fill_((depth_unit - 0.5) / 0.25);
  return input;
}

TEST(CheckMontageTest, FramesAreSpreadOverEachConditionInNameOrder) {
  const std::vector<std::string> conditions = {"void, ideal", "room, ideal", "void, ideal",
                                               "void, ideal", "room, ideal", "void, ideal"};
  const auto picks = montageFrames(conditions, 2);
  ASSERT_EQ(picks.size(), 2u);
  EXPECT_EQ(picks[0].first, "room, ideal");
  EXPECT_EQ(picks[0].second, (std::vector<int64_t>{1, 4}));
  EXPECT_EQ(picks[1].first, "void, ideal");
  EXPECT_EQ(picks[1].second, (std::vector<int64_t>{0, 3}));  // of 0, 2, 3, 5: the 1st and 3rd
  EXPECT_EQ(montageFrames(conditions, 10)[1].second, (std::vector<int64_t>{0, 2, 3, 5}));
  EXPECT_THROW(montageFrames(conditions, 0), InvalidArgumentError);
}

TEST(CheckMontageTest, TheLabelIsGreenTheEstimateRedAndBothYellow) {
  const torch::Tensor input = greyInput(2, 0.0);
  const torch::Tensor label = torch::tensor({{1, 0}, {1, 0}}, torch::kUInt8);
  const torch::Tensor estimate = torch::tensor({{0, 1}, {1, 0}}, torch::kUInt8);
  const cv::Mat tile = overlayTile(input, label, estimate, 4);  // each pixel 2 x 2
  ASSERT_EQ(tile.size(), cv::Size(4, 4));
  ASSERT_EQ(tile.type(), CV_8UC3);
  const cv::Vec3b grey(128, 128, 128);                           // 0.5 of 255, rounded
  EXPECT_EQ(tile.at<cv::Vec3b>(0, 0), cv::Vec3b(64, 191, 64));   // label only (BGR)
  EXPECT_EQ(tile.at<cv::Vec3b>(1, 3), cv::Vec3b(64, 64, 191));   // estimate only
  EXPECT_EQ(tile.at<cv::Vec3b>(3, 1), cv::Vec3b(64, 191, 191));  // both
  EXPECT_EQ(tile.at<cv::Vec3b>(3, 3), grey);                     // neither: the RGB
  EXPECT_THROW(overlayTile(torch::zeros({3, 2, 2}), label, estimate, 4), InvalidArgumentError);
}

TEST(CheckMontageTest, DepthIsBrightNearAndBlackFar) {
  EXPECT_EQ(depthTile(greyInput(2, 0.0), 8).at<cv::Vec3b>(5, 5), cv::Vec3b(255, 255, 255));
  EXPECT_EQ(depthTile(greyInput(2, 1.0), 8).at<cv::Vec3b>(5, 5), cv::Vec3b(0, 0, 0));
}

TEST(CheckMontageTest, TheSheetHasARowPerConditionAndEachFramesTiles) {
  NetworkConfig config;
  config.input_size = 32;
  MultiTaskUNet network(config);
  Samples frames;
  frames.inputs =
      torch::stack({greyInput(32, 0.2), greyInput(32, 0.4), greyInput(32, 0.6)}).to(torch::kHalf);
  frames.masks = torch::zeros({3, 1, 32, 32}, torch::kUInt8);
  const std::vector<std::string> conditions = {"void, ideal", "room, ideal", "void, ideal"};
  const int tile = 32;
  const cv::Mat sheet = checkMontage(network, frames, conditions, 2, tile);
  // Rows: a tile and its caption; columns: the names' strip, then two tiles a frame.
  const int row_height = sheet.rows / 2, frame_width = (sheet.cols - 200) / 2;
  EXPECT_EQ(sheet.rows, 2 * row_height);
  EXPECT_GE(row_height, tile);
  EXPECT_EQ(sheet.cols, 200 + 2 * frame_width);
  EXPECT_GE(frame_width, 2 * tile);
  // The second row is "void, ideal": frames 0 and 2; the depth tile of frame 2 is its second's.
  const cv::Rect depth_of_frame_2(200 + frame_width + tile, row_height, tile, tile);
  const cv::Mat expected = depthTile(frames.inputs[2].to(torch::kFloat), tile);
  EXPECT_EQ(cv::norm(sheet(depth_of_frame_2), expected, cv::NORM_INF), 0.0);
  EXPECT_TRUE(network->is_training()) << "the network's mode is given back";
  EXPECT_THROW(checkMontage(network, frames, {"void, ideal"}, 2, tile), InvalidArgumentError);
}

}  // namespace
}  // namespace learning
}  // namespace occlusion_env
