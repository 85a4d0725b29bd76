// ROS 2's tf2 BufferCore, built from ros2/geometry2's sources at test time (tests/oracle ros2_core()), driven by
// lines on stdin (a frame named "-" is the empty name; an authority is one word):
//   new CACHE_NS                                                    a new BufferCore with that cache time
//   set PARENT CHILD NS TX TY TZ QX QY QZ QW STATIC AUTHORITY          ->  1 or 0 (logs on stderr)
//   lookup TARGET SOURCE NS | full TARGET NS SOURCE NS FIXED        ->  T NS TX TY TZ QX QY QZ QW (%a) or E CLASS TEXT
//   can TARGET SOURCE NS                                            ->  1 or 0
//   yaml                                                            ->  its length, then allFramesAsYAML
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include "tf2/buffer_core.h"
#include "tf2/exceptions.h"

static std::string esc(const char* w) { std::string s(w), o; for (char c : s) { if (c == '\n') o += "\\n"; else o += c; } return o; }
static std::string unq(const std::string& s) { return s == "-" ? "" : s; }  // "-" = empty name

int main() {
  tf2::BufferCore core(tf2::Duration(std::chrono::seconds(10)));
  std::unique_ptr<tf2::BufferCore> owned;
  tf2::BufferCore* b = &core;
  std::string line;
  while (std::getline(std::cin, line)) {
    std::istringstream in(line);
    std::string cmd;
    in >> cmd;
    if (cmd == "new") {  // new CACHE_NS
      long long ns; in >> ns;
      owned.reset(new tf2::BufferCore(tf2::Duration(std::chrono::nanoseconds(ns))));
      b = owned.get();
      std::printf("ok\n");
    } else if (cmd == "set") {
      geometry_msgs::msg::TransformStamped t;
      std::string parent, child, auth; long long ns; int st;
      double v[7];
      in >> parent >> child >> ns;
      for (double& x : v) { std::string tok; in >> tok; x = std::strtod(tok.c_str(), nullptr); }
      in >> st >> auth;
      t.header.frame_id = unq(parent); t.child_frame_id = unq(child);
      t.header.stamp.sec = static_cast<int32_t>(ns / 1000000000LL); t.header.stamp.nanosec = static_cast<uint32_t>(ns % 1000000000LL);
      t.transform.translation.x = v[0]; t.transform.translation.y = v[1]; t.transform.translation.z = v[2];
      t.transform.rotation.x = v[3]; t.transform.rotation.y = v[4]; t.transform.rotation.z = v[5]; t.transform.rotation.w = v[6];
      std::fflush(stdout);
      bool ok = b->setTransform(t, auth, st != 0);
      std::fflush(stderr);
      std::printf("%d\n", ok ? 1 : 0);
    } else if (cmd == "lookup" || cmd == "can") {
      std::string target, source; long long ns;
      in >> target >> source >> ns;
      tf2::TimePoint tp{std::chrono::nanoseconds(ns)};
      if (cmd == "can") {
        std::string err;
        bool ok = b->canTransform(unq(target), unq(source), tp, &err);
        std::printf("%d\n", ok ? 1 : 0);
        continue;
      }
      try {
        auto r = b->lookupTransform(unq(target), unq(source), tp);
        long long out = (long long)r.header.stamp.sec * 1000000000LL + r.header.stamp.nanosec;
        const auto& tr = r.transform.translation; const auto& q = r.transform.rotation;
        std::printf("T %lld %a %a %a %a %a %a %a\n", out, tr.x, tr.y, tr.z, q.x, q.y, q.z, q.w);
      } catch (const tf2::ForwardExtrapolationException& e) { std::printf("E Forward %s\n", esc(e.what()).c_str());
      } catch (const tf2::BackwardExtrapolationException& e) { std::printf("E Backward %s\n", esc(e.what()).c_str());
      } catch (const tf2::NoDataForExtrapolationException& e) { std::printf("E NoData %s\n", esc(e.what()).c_str());
      } catch (const tf2::ExtrapolationException& e) { std::printf("E Extrapolation %s\n", esc(e.what()).c_str());
      } catch (const tf2::ConnectivityException& e) { std::printf("E Connectivity %s\n", esc(e.what()).c_str());
      } catch (const tf2::LookupException& e) { std::printf("E Lookup %s\n", esc(e.what()).c_str());
      } catch (const tf2::InvalidArgumentException& e) { std::printf("E InvalidArgument %s\n", esc(e.what()).c_str());
      } catch (const std::exception& e) { std::printf("E Other %s\n", esc(e.what()).c_str()); }
    } else if (cmd == "full") {  // full target ttime source stime fixed
      std::string target, source, fixed; long long tt, st;
      in >> target >> tt >> source >> st >> fixed;
      try {
        auto r = b->lookupTransform(target, tf2::TimePoint{std::chrono::nanoseconds(tt)}, source, tf2::TimePoint{std::chrono::nanoseconds(st)}, fixed);
        long long out = (long long)r.header.stamp.sec * 1000000000LL + r.header.stamp.nanosec;
        const auto& tr = r.transform.translation; const auto& q = r.transform.rotation;
        std::printf("T %lld %a %a %a %a %a %a %a\n", out, tr.x, tr.y, tr.z, q.x, q.y, q.z, q.w);
      } catch (const std::exception& e) { std::printf("E X %s\n", esc(e.what()).c_str()); }
    } else if (cmd == "yaml") {
      std::string y = b->allFramesAsYAML();
      std::printf("%zu\n%s", y.size(), y.c_str());
    }
    std::fflush(stdout);
  }
}
