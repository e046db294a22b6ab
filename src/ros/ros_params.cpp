#include "preadaptive_mrac/ros/ros_params.hpp"

#include <cstdlib>
#include <regex>

namespace preadaptive_mrac {
namespace ros1 {

namespace {
// rosparam and roslaunch read YAML 1.1 (PyYAML), where a number with an exponent but no dot or
// no sign in it ("1e-3", "1.0e300") is a string; the CLI's reader (YAML 1.2) reads a number.
// Such a string is read as the CLI reads it, so one file means the same on both paths.
bool yaml12Number(const std::string& s, double* out) {
  static const std::regex kFloat(R"([-+]?([0-9]+(\.[0-9]*)?|\.[0-9]+)[eE][-+]?[0-9]+)");
  if (s.size() > 64 || !std::regex_match(s, kFloat)) return false;
  *out = std::strtod(s.c_str(), nullptr);
  return true;
}
}  // namespace

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
    case XmlRpc::XmlRpcValue::TypeString: {
      const std::string text = static_cast<std::string>(c);
      double d = 0.0;
      return yaml12Number(text, &d) ? ParamValue::makeDouble(d) : ParamValue::makeString(text);
    }
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

}  // namespace ros1
}  // namespace preadaptive_mrac
