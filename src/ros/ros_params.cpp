#include "preadaptive_mrac/ros/ros_params.hpp"

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

}  // namespace ros1
}  // namespace preadaptive_mrac
