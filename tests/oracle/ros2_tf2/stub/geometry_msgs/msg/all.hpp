#pragma once
#include <string>
#include <array>
#include "builtin_interfaces/msg/time.hpp"
namespace std_msgs { namespace msg { struct Header { builtin_interfaces::msg::Time stamp; std::string frame_id; }; } }
namespace geometry_msgs { namespace msg {
struct Vector3 { double x = 0, y = 0, z = 0; };
struct Point { double x = 0, y = 0, z = 0; };
struct Quaternion { double x = 0, y = 0, z = 0, w = 1; };
struct QuaternionStamped { std_msgs::msg::Header header; Quaternion quaternion; };
struct Transform { Vector3 translation; Quaternion rotation; };
struct TransformStamped { std_msgs::msg::Header header; std::string child_frame_id; Transform transform; };
struct Twist { Vector3 linear, angular; };
struct VelocityStamped { std_msgs::msg::Header header; std::string body_frame_id; std::string reference_frame_id; Twist velocity; };
} }
