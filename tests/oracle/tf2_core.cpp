// ROS 1's tf2 BufferCore (Debian's libtf2) driven by lines on stdin, for the tests: C++ holds every
// stamp in integer nanoseconds, where tf2_py (tf2_harness.py) rounds each through a double.
// Its one argument, if given, is the cache time in seconds (tf2's default, 10, without).
//   set PARENT CHILD NS TX TY TZ QX QY QZ QW STATIC AUTHORITY  ->  1 or 0 (logs on stderr)
//   lookup TARGET SOURCE NS                                    ->  T NS TX TY TZ QX QY QZ QW (%a), or E CLASS MESSAGE
#include <geometry_msgs/TransformStamped.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

static ros::Time time_of(long long ns) { return ros::Time(ns / 1000000000LL, ns % 1000000000LL); }

int main(int argc, char** argv) {
    tf2::BufferCore core(ros::Duration(argc > 1 ? std::atoi(argv[1]) : 10));
    std::string line;
    while (std::getline(std::cin, line)) {
        std::istringstream in(line);
        std::string command, target, source;
        long long ns = 0;
        in >> command >> target >> source >> ns;
        if (command == "set") {
            geometry_msgs::TransformStamped t;
            t.header.frame_id = target;
            t.child_frame_id = source;
            t.header.stamp = time_of(ns);
            double v[7];
            for (double& x : v) {
                std::string token;
                in >> token;
                x = std::strtod(token.c_str(), nullptr);
            }
            int is_static = 0;
            std::string authority;
            in >> is_static >> authority;
            t.transform.translation.x = v[0], t.transform.translation.y = v[1], t.transform.translation.z = v[2];
            t.transform.rotation.x = v[3], t.transform.rotation.y = v[4], t.transform.rotation.z = v[5];
            t.transform.rotation.w = v[6];
            const bool ok = core.setTransform(t, authority, is_static != 0);
            std::fflush(stderr);
            std::printf("%d\n", ok ? 1 : 0);
        } else if (command == "lookup") {
            try {
                const geometry_msgs::TransformStamped r = core.lookupTransform(target, source, time_of(ns));
                const auto& p = r.transform.translation;
                const auto& q = r.transform.rotation;
                std::printf("T %lld %a %a %a %a %a %a %a\n", static_cast<long long>(r.header.stamp.toNSec()), p.x, p.y,
                            p.z, q.x, q.y, q.z, q.w);
            } catch (const tf2::ExtrapolationException& e) {
                std::printf("E ExtrapolationException %s\n", e.what());
            } catch (const tf2::ConnectivityException& e) {
                std::printf("E ConnectivityException %s\n", e.what());
            } catch (const tf2::LookupException& e) {
                std::printf("E LookupException %s\n", e.what());
            } catch (const tf2::InvalidArgumentException& e) {
                std::printf("E InvalidArgumentException %s\n", e.what());
            }
        }
        std::fflush(stdout);
    }
}
