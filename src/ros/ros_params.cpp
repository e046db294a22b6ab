#include "preadaptive_mrac/ros/ros_params.hpp"

#include <ros/ros.h>

#include <cstdio>

namespace preadaptive_mrac {
namespace ros1 {

ParamValue fromXmlRpc(const XmlRpc::XmlRpcValue& v) {
  // XmlRpcValue's accessors are non-const (they may convert in place); work on a copy.
  XmlRpc::XmlRpcValue c = v;
  switch (c.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return ParamValue::makeBool(static_cast<bool>(c));
    case XmlRpc::XmlRpcValue::TypeInt:
      return ParamValue::makeInt(static_cast<int>(c));
    case XmlRpc::XmlRpcValue::TypeDouble:
      return ParamValue::makeDouble(static_cast<double>(c));
    case XmlRpc::XmlRpcValue::TypeString:
      return ParamValue::makeString(static_cast<std::string>(c));
    case XmlRpc::XmlRpcValue::TypeArray: {
      std::vector<ParamValue> items;
      items.reserve(static_cast<size_t>(c.size()));
      for (int i = 0; i < c.size(); ++i) items.push_back(fromXmlRpc(c[i]));
      return ParamValue::makeList(std::move(items));
    }
    case XmlRpc::XmlRpcValue::TypeStruct: {
      ParamValue m = ParamValue::makeMap();
      for (auto it = c.begin(); it != c.end(); ++it) m.map()[it->first] = fromXmlRpc(it->second);
      return m;
    }
    default:
      return ParamValue();
  }
}

ParamValue readPrivateParams() {
  XmlRpc::XmlRpcValue v;
  // The node's private namespace is its resolved name; getParam on it returns the subtree.
  if (!ros::param::get(ros::this_node::getName(), v)) return ParamValue::makeMap();
  if (v.getType() != XmlRpc::XmlRpcValue::TypeStruct) return ParamValue::makeMap();
  return fromXmlRpc(v);
}

KeyStyle privateKeyStyle() {
  KeyStyle s;
  s.root = ros::this_node::getName() + "/";
  s.separator = '/';
  return s;
}

void logConfigProblems(const std::vector<std::string>& problems) {
  ROS_FATAL("%s: refusing to start, %zu parameter problem(s):", ros::this_node::getName().c_str(),
            problems.size());
  for (const auto& p : problems) ROS_FATAL("  %s", p.c_str());
}

void printAfterShutdown(const std::string& line, bool error) {
  std::FILE* f = error ? stderr : stdout;
  std::fprintf(f, "[%s] %s: %s\n", error ? "ERROR" : " INFO", ros::this_node::getName().c_str(),
               line.c_str());
  std::fflush(f);
}

}  // namespace ros1
}  // namespace preadaptive_mrac
