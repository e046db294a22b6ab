#include "preadaptive_mrac/io/weights_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "preadaptive_mrac/core/schema/params.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

namespace preadaptive_mrac {

namespace {
constexpr const char* kFormatTag = "preadaptive_mrac/weights";

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

std::string dirOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}
}  // namespace

std::string weightsToYaml(const LearnedState& s) {
  std::ostringstream os;
  os << "# Preadaptation network theta_hat_I = W^T sigma(V^T [e, |e_dot|]) (preadaptive_mrac)\n";
  os << "format: " << kFormatTag << "\n";
  os << "version: " << kWeightsFormatVersion << "\n";
  os << "inputs: " << kNetInputs << "\n";
  os << "hidden: " << s.hidden() << "\n";
  os << "outputs: " << s.outputs() << "\n";
  os << "seed: " << s.seed << "\n";
  os << "init_scale: " << num(s.init_scale) << "\n";
  os << "episodes: " << s.episodes << "\n";
  os << "V:  # inputs x hidden\n";
  for (int k = 0; k < s.V.rows(); ++k) {
    os << "  - [";
    for (int j = 0; j < s.V.cols(); ++j) os << (j ? ", " : "") << num(s.V(k, j));
    os << "]\n";
  }
  os << "W:  # hidden x outputs\n";
  for (int j = 0; j < s.W.rows(); ++j) {
    os << "  - [";
    for (int i = 0; i < s.W.cols(); ++i) os << (i ? ", " : "") << num(s.W(j, i));
    os << "]\n";
  }
  // Version 2: the regimes pa_robust remembers (theta, how often used, last-use stamp);
  // version 3: with each its loss of effectiveness and the information of that fit.
  if (s.regimes.empty()) {
    os << "regimes: []  # remembered by pa_robust: theta, uses, last_used, loss, loss_info\n";
  } else {
    os << "regimes:  # remembered by pa_robust: theta, uses, last_used, loss, loss_info\n";
    for (const RegimeEntry& e : s.regimes) {
      os << "  - theta: [";
      for (Eigen::Index i = 0; i < e.theta.size(); ++i) os << (i ? ", " : "") << num(e.theta[i]);
      os << "]\n    uses: " << e.uses << "\n    last_used: " << e.last_used
         << "\n    loss: " << num(e.loss) << "\n    loss_info: " << num(e.loss_info) << "\n";
    }
  }
  return os.str();
}

void saveWeights(const std::string& path, const LearnedState& s) {
  const std::string text = weightsToYaml(s);
  std::string tmpl = path + ".tmp.XXXXXX";
  std::vector<char> name(tmpl.begin(), tmpl.end());
  name.push_back('\0');
  const int fd = mkstemp(name.data());
  if (fd < 0)
    throw WeightsError(path + ": cannot create a temporary file beside it (" +
                       std::strerror(errno) + "); the previous file is untouched");
  const std::string tmp(name.data());
  auto fail = [&](const std::string& what) {
    const int err = errno;
    ::close(fd);
    ::unlink(tmp.c_str());
    throw WeightsError(path + ": " + what + " (" + std::strerror(err) +
                       "); the previous file is untouched");
  };
  size_t off = 0;
  while (off < text.size()) {
    const ssize_t w = ::write(fd, text.data() + off, text.size() - off);
    if (w < 0) {
      if (errno == EINTR) continue;
      fail("write failed");
    }
    off += static_cast<size_t>(w);
  }
  if (::fchmod(fd, 0644) != 0) fail("chmod failed");
  if (::fsync(fd) != 0) fail("fsync failed");
  if (::close(fd) != 0) {
    ::unlink(tmp.c_str());
    throw WeightsError(path + ": close failed; the previous file is untouched");
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw WeightsError(path + ": rename failed (" + std::strerror(err) +
                       "); the previous file is untouched");
  }
  const int dfd = ::open(dirOf(path).c_str(), O_RDONLY | O_DIRECTORY);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

LearnedState parseWeights(const std::string& text, const std::string& origin, int expected_hidden,
                          int expected_outputs) {
  ParamValue tree;
  try {
    tree = parseYaml(text, origin);
  } catch (const FileError& e) {
    throw WeightsError(std::string("corrupt weights file: ") + e.what());
  }
  ParamReader r(tree, KeyStyle{origin + ": ", '.'});
  const std::string format = r.getString("format");
  if (r.has("format") && format != kFormatTag)
    r.fail("format", "expected '" + std::string(kFormatTag) + "', got '" + format + "'");
  const std::int64_t version = r.getInt("version");
  if (r.has("version") && (version < 1 || version > kWeightsFormatVersion))
    r.fail("version", "unsupported version " + std::to_string(version) +
                          " (this build reads 1 to " + std::to_string(kWeightsFormatVersion) + ")");
  const std::int64_t inputs = r.getInt("inputs");
  if (r.has("inputs") && inputs != kNetInputs)
    r.fail("inputs", "must be " + std::to_string(kNetInputs) + ", got " + std::to_string(inputs));
  const std::int64_t hidden = r.getInt("hidden");
  const std::int64_t outputs = r.getInt("outputs");
  if (r.has("hidden") && (hidden < 1 || hidden > kMaxHidden))
    r.fail("hidden",
           "must be in [1, " + std::to_string(kMaxHidden) + "], got " + std::to_string(hidden));
  if (r.has("outputs") && (outputs < 1 || outputs > kMaxStates))
    r.fail("outputs",
           "must be in [1, " + std::to_string(kMaxStates) + "], got " + std::to_string(outputs));
  LearnedState s;
  const std::int64_t seed = r.getInt("seed");
  s.seed = static_cast<std::uint64_t>(seed < 0 ? 0 : seed);
  s.init_scale = r.getDouble("init_scale");
  s.episodes = r.getInt("episodes");
  if (r.has("episodes") && s.episodes < 0) r.fail("episodes", "must be >= 0");
  if (!r.ok())
    throw WeightsError(std::string("corrupt weights file: ") + ConfigError(r.problems()).what());
  const Eigen::MatrixXd V = r.getMatrix("V", kNetInputs, static_cast<int>(hidden));
  const Eigen::MatrixXd W = r.getMatrix("W", static_cast<int>(hidden), static_cast<int>(outputs));
  // Regimes (version 2; version 1 files have none). Each theta has the network's output size.
  if (version >= 2 && r.has("regimes")) {
    const ParamValue* list = tree.findPath("regimes");
    if (list->type() != ParamValue::Type::kList) {
      r.fail("regimes", "expected a list, got " + list->describe());
    } else {
      r.markUsed("regimes");
      for (size_t k = 0; k < list->list().size(); ++k) {
        const std::string key = "regimes." + std::to_string(k);
        const ParamValue& item = list->list()[k];
        if (item.type() != ParamValue::Type::kMap) {
          r.fail(key, "expected a map {theta, uses, last_used}, got " + item.describe());
          continue;
        }
        for (const auto& kv : item.map()) {
          const bool v3 = kv.first == "loss" || kv.first == "loss_info";
          if (kv.first != "theta" && kv.first != "uses" && kv.first != "last_used" &&
              !(v3 && version >= 3))
            r.fail(key + "." + kv.first, "unknown key");
        }
        RegimeEntry e;
        e.theta = r.getVector(key + ".theta", static_cast<int>(outputs));
        e.uses = r.getInt(key + ".uses");
        e.last_used = r.getInt(key + ".last_used");
        if (r.has(key + ".uses") && e.uses < 0) r.fail(key + ".uses", "must be >= 0");
        if (version >= 3) {  // optional: absent, no loss identified
          e.loss = r.getDouble(key + ".loss", 0.0);
          e.loss_info = r.getDouble(key + ".loss_info", 0.0);
          if (!std::isfinite(e.loss)) r.fail(key + ".loss", "must be finite");
          if (!(e.loss_info >= 0.0) || !std::isfinite(e.loss_info))
            r.fail(key + ".loss_info", "must be finite and >= 0");
        }
        s.regimes.push_back(e);
      }
    }
  } else if (version >= 2) {
    r.fail("regimes", "missing (version 2 files list the remembered regimes, [] when none)");
  }
  r.rejectUnusedUnder("");
  if (!r.ok())
    throw WeightsError(std::string("corrupt weights file: ") + ConfigError(r.problems()).what());
  if ((expected_hidden >= 0 && hidden != expected_hidden) ||
      (expected_outputs >= 0 && outputs != expected_outputs))
    throw WeightsError(origin + ": weights are for hidden=" + std::to_string(hidden) +
                       ", outputs=" + std::to_string(outputs) +
                       " but the controller needs hidden=" + std::to_string(expected_hidden) +
                       ", outputs=" + std::to_string(expected_outputs) +
                       " (controller.preadaptation.hidden and the plant's state size)");
  s.V = V;
  s.W = W;
  return s;
}

LearnedState loadWeights(const std::string& path, int expected_hidden, int expected_outputs) {
  std::ifstream in(path);
  if (!in)
    throw WeightsError(path + ": cannot open weights file (" + std::string(std::strerror(errno)) +
                       ")");
  std::stringstream ss;
  ss << in.rdbuf();
  if (ss.str().empty()) throw WeightsError(path + ": corrupt weights file: it is empty");
  return parseWeights(ss.str(), path, expected_hidden, expected_outputs);
}

}  // namespace preadaptive_mrac
