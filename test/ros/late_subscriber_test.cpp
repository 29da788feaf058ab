// Late subscribers (test/ros/late_subscriber.test): the simulator has reset at start-up and does
// not step; a subscriber and a tf listener that start afterwards still get the view, stamped with
// the reset's stamp, and depth_image_proc's point cloud of it lands on the objects.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Geometry>
#include <cmath>
#include <mutex>
#include <optional>
#include <vector>

#include "occlusion_env/ros/names.hpp"

namespace occlusion_env {
namespace {

template <typename Message>
class Latest {
 public:
  Latest(ros::NodeHandle& node, const std::string& topic)
      : subscriber_(node.subscribe<Message>(topic, 1, [this](const typename Message::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          message_ = *m;
        })) {}
  std::optional<Message> get() {
    std::lock_guard<std::mutex> lock(mutex_);
    return message_;
  }

 private:
  std::mutex mutex_;
  std::optional<Message> message_;
  ros::Subscriber subscriber_;
};

// Waits up to `seconds` for every optional to hold a message.
template <typename... Latests>
bool waitForAll(double seconds, Latests&... latests) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::WallTime::now() < deadline) {
    if ((latests.get().has_value() && ...)) return true;
    ros::WallDuration(0.05).sleep();
  }
  return false;
}

TEST(LateSubscriber, GetsTheCurrentViewItsTfAndAPointCloudOnTheObjects) {
  ros::NodeHandle node(names::kNamespace);
  // The simulator resets at start-up, before it offers its services: once reset is there, the
  // view exists. Then wait a little longer, so that every subscription below is a late one.
  ASSERT_TRUE(
      ros::service::waitForService(node.resolveName(names::kResetService), ros::Duration(30.0)));
  ros::WallDuration(1.0).sleep();

  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  Latest<sensor_msgs::Image> rgb(node, names::kRgbImageTopic);
  Latest<sensor_msgs::CameraInfo> mask_info(node, names::kOcclusionMaskCameraInfoTopic);
  Latest<sensor_msgs::Image> instance(node, names::kInstanceMaskTopic);
  Latest<sensor_msgs::PointCloud2> cloud(node, names::kPointsTopic);
  Latest<visualization_msgs::MarkerArray> markers(node, names::kSceneMarkersTopic);
  ASSERT_TRUE(waitForAll(20.0, rgb, mask_info, instance, cloud, markers))
      << "rgb " << rgb.get().has_value() << ", mask camera_info " << mask_info.get().has_value()
      << ", instance " << instance.get().has_value() << ", cloud " << cloud.get().has_value()
      << ", markers " << markers.get().has_value();

  const ros::Time stamp = rgb.get()->header.stamp;
  EXPECT_FALSE(stamp.isZero());
  EXPECT_EQ(mask_info.get()->header.stamp, stamp);
  EXPECT_EQ(instance.get()->header.stamp, stamp);
  EXPECT_EQ(cloud.get()->header.stamp, stamp);
  EXPECT_EQ(cloud.get()->header.frame_id, names::kOpticalFrame);
  EXPECT_EQ(mask_info.get()->width, 128u);

  // tf answers at the view's stamp, although the listener started after it.
  std::string error;
  ASSERT_TRUE(buffer.canTransform(names::kWorldFrame, names::kOpticalFrame, stamp,
                                  ros::Duration(5.0), &error))
      << error;
  const Eigen::Isometry3d world_from_optical = tf2::transformToEigen(
      buffer.lookupTransform(names::kWorldFrame, names::kOpticalFrame, stamp));

  // Each object's bounding box in the world, from its marker (the render mesh).
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const visualization_msgs::Marker& marker : markers.get()->markers) {
    if (marker.action != visualization_msgs::Marker::ADD) continue;
    Eigen::AlignedBox3d box;
    const Eigen::Vector3d offset(marker.pose.position.x, marker.pose.position.y,
                                 marker.pose.position.z);
    for (const geometry_msgs::Point& p : marker.points)
      box.extend(offset + Eigen::Vector3d(p.x, p.y, p.z));
    boxes.push_back(box);
  }
  ASSERT_GE(boxes.size(), 2u);

  int points = 0, on_objects = 0;
  for (sensor_msgs::PointCloud2ConstIterator<float> x(*cloud.get(), "x"), y(*cloud.get(), "y"),
       z(*cloud.get(), "z");
       x != x.end(); ++x, ++y, ++z) {
    if (!std::isfinite(*x) || !std::isfinite(*y) || !std::isfinite(*z)) continue;
    ++points;
    const Eigen::Vector3d world = world_from_optical * Eigen::Vector3d(*x, *y, *z);
    for (const Eigen::AlignedBox3d& box : boxes) {
      const Eigen::AlignedBox3d grown(box.min().array() - 0.01, box.max().array() + 0.01);
      if (grown.contains(world)) {
        ++on_objects;
        break;
      }
    }
  }
  EXPECT_GT(points, 200) << "the objects cover part of the image";
  EXPECT_EQ(on_objects, points) << "every point lies on an object";
}

}  // namespace
}  // namespace occlusion_env

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "late_subscriber_test");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
