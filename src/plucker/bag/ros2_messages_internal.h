// The ROS 2 (CDR) layouts of sensor_msgs/msg/{Imu,Image,CompressedImage,PointCloud2}, decoded
// into and encoded from the ROS 1 message structs the bag reader already converts, so that a
// `.db3` bag yields exactly what a `.bag` does. Private to the bag layer (ROS headers).
#pragma once

#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstdint>
#include <string>
#include <vector>

namespace plucker {
namespace bag {
namespace ros2 {

// "sensor_msgs/msg/Imu" -> "sensor_msgs/Imu" and back; other names are returned as they are.
std::string Ros1Type(const std::string& ros2_type);
std::string Ros2Type(const std::string& ros1_type);

// Throw CdrError: truncated payload, an encapsulation other than CDR little-endian, a negative
// stamp, a string without its NUL. Trailing bytes are allowed (padding).
void Decode(const std::uint8_t* data, std::size_t size, sensor_msgs::Imu* m);
void Decode(const std::uint8_t* data, std::size_t size, sensor_msgs::Image* m);
void Decode(const std::uint8_t* data, std::size_t size, sensor_msgs::CompressedImage* m);
void Decode(const std::uint8_t* data, std::size_t size, sensor_msgs::PointCloud2* m);

std::vector<std::uint8_t> Encode(const sensor_msgs::Imu& m);
std::vector<std::uint8_t> Encode(const sensor_msgs::Image& m);
std::vector<std::uint8_t> Encode(const sensor_msgs::CompressedImage& m);
std::vector<std::uint8_t> Encode(const sensor_msgs::PointCloud2& m);

}  // namespace ros2
}  // namespace bag
}  // namespace plucker
