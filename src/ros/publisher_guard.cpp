#include "preadaptive_mrac/ros/publisher_guard.hpp"

#include <algorithm>
#include <cctype>

namespace preadaptive_mrac {
namespace ros1 {

bool validCallerName(const std::string& name, std::string* why) {
  const auto fail = [&](const std::string& what) {
    if (why) *why = what;
    return false;
  };
  if (name.empty()) return fail("empty");
  if (name[0] == '~')
    return fail("a private name ('~...') is never a caller id; give the node's name");
  if (!(std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '/'))
    return fail("must start with a letter or '/'");
  for (char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '/'))
      return fail(std::string("character '") + c + "' cannot be in a node name");
  }
  if (name == "/" || name.back() == '/' || name.find("//") != std::string::npos)
    return fail("empty name component");
  return true;
}

std::string resolveCallerName(const std::string& ns, const std::string& name) {
  if (!name.empty() && name[0] == '/') return name;
  std::string base = ns.empty() ? "/" : ns;
  if (base[0] != '/') base = "/" + base;
  if (base.back() != '/') base += '/';
  return base + name;
}

std::vector<std::string> resolveCallerNames(const std::string& ns,
                                            const std::vector<std::string>& names) {
  std::vector<std::string> out;
  out.reserve(names.size());
  for (const auto& n : names) out.push_back(resolveCallerName(ns, n));
  return out;
}

PublisherGuard::PublisherGuard(std::vector<std::string> accepted, std::string key, Warn warn)
    : accepted_(std::move(accepted)), key_(std::move(key)), warn_(std::move(warn)) {}

bool PublisherGuard::accepts(const std::string& caller_id) const {
  return accepted_.empty() ||
         std::find(accepted_.begin(), accepted_.end(), caller_id) != accepted_.end();
}

bool PublisherGuard::admit(const std::string& caller_id, const std::string& topic) {
  if (accepts(caller_id)) return true;
  dropped_.fetch_add(1, std::memory_order_relaxed);
  std::string warning;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto key = std::make_pair(caller_id, topic);
    auto it = named_.find(key);
    if (it != named_.end()) {
      ++it->second;
    } else if (named_.size() < kMaxNamed) {
      named_.emplace(key, 1);
      warning = "dropping messages on " + topic + " from " + caller_id +
                ": not an expected publisher (" + key_ + ": " + acceptedText() +
                "); further ones from it are counted on /diagnostics, not logged";
      if (named_.size() == kMaxNamed)
        warning += " (" + std::to_string(kMaxNamed) +
                   " foreign publishers named: any others are counted without a name)";
    } else {
      ++unnamed_;
    }
  }
  // Outside the lock: the callback may log (and a log call may be slow).
  if (!warning.empty() && warn_) warn_(warning);
  return false;
}

std::string PublisherGuard::acceptedText() const {
  if (accepted_.empty()) return "any publisher";
  std::string s;
  for (std::size_t i = 0; i < accepted_.size(); ++i) s += (i ? ", " : "") + accepted_[i];
  return s;
}

std::string PublisherGuard::droppedText() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (named_.empty()) return "none";
  std::string s;
  for (const auto& kv : named_) {
    if (!s.empty()) s += ", ";
    s += kv.first.first + " on " + kv.first.second + ": " + std::to_string(kv.second);
  }
  if (unnamed_ > 0)
    s += ", and " + std::to_string(unnamed_) + " more message(s) from other publishers";
  return s;
}

}  // namespace ros1
}  // namespace preadaptive_mrac
