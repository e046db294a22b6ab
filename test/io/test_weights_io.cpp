// Weights file: round trip, corrupt and mismatched files, atomic save.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "preadaptive_mrac/io/weights_io.hpp"

using namespace preadaptive_mrac;

namespace {
std::string tmpDir() {
  char tmpl[] = "/tmp/pmrac_weights_XXXXXX";
  return mkdtemp(tmpl);
}
void writeFile(const std::string& p, const std::string& text) { std::ofstream(p) << text; }
std::string readFile(const std::string& p) {
  std::stringstream ss;
  ss << std::ifstream(p).rdbuf();
  return ss.str();
}
std::string errorOf(const std::string& text, int hidden = 3, int outputs = 3) {
  try {
    parseWeights(text, "w.yaml", hidden, outputs);
  } catch (const WeightsError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST(WeightsIo, SaveLoadGivesIdenticalOutputs) {
  PreadaptNetwork net(3, 3, 99, 0.7);
  // Learn once so the weights are not just the seeded ones.
  Vec g(3);
  g << 0.1, -0.2, 0.3;
  net.learn(NetInput(0.005, 0.04), g, 10.0);
  const std::string dir = tmpDir();
  const std::string path = dir + "/w.yaml";
  saveWeights(path, net.state());
  const LearnedState back = loadWeights(path, 3, 3);
  EXPECT_EQ(back.seed, 99u);
  EXPECT_EQ(back.episodes, 1);
  EXPECT_EQ(back.init_scale, 0.7);
  EXPECT_EQ((back.W - net.state().W).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((back.V - net.state().V).cwiseAbs().maxCoeff(), 0.0);
  PreadaptNetwork loaded(back);
  for (double e : {-0.02, 0.005, 0.3}) {
    Vec a, b;
    net.forward(NetInput(e, 0.05), &a);
    loaded.forward(NetInput(e, 0.05), &b);
    EXPECT_EQ((a - b).cwiseAbs().maxCoeff(), 0.0);
  }
}

TEST(WeightsIo, CorruptFilesAreClearErrors) {
  const std::string good = weightsToYaml(PreadaptNetwork(3, 3, 1, 1.0).state());
  EXPECT_EQ(errorOf(good), "no error");
  // Truncated mid-way: W has too few rows.
  const std::string truncated = good.substr(0, good.rfind("  - ["));
  EXPECT_NE(errorOf(truncated).find("W"), std::string::npos) << errorOf(truncated);
  // Not YAML at all.
  EXPECT_NE(errorOf("V: [[1, 2\nW: ]]]").find("malformed YAML"), std::string::npos);
  // Another format, another version.
  std::string other = good;
  other.replace(other.find("preadaptive_mrac/weights"), 24, "something/else");
  EXPECT_NE(errorOf(other).find("format"), std::string::npos);
  std::string v4 = good;
  v4.replace(v4.find("version: 3"), 10, "version: 4");
  EXPECT_NE(errorOf(v4).find("unsupported version 4"), std::string::npos);
  // A NaN weight.
  std::string nan = good;
  nan.replace(nan.find("W:") + good.substr(good.find("W:")).find("[") + 1, 0, ".nan, ");
  EXPECT_NE(errorOf(nan).find("W"), std::string::npos) << errorOf(nan);
  // A missing field.
  std::string noseed = good;
  noseed.erase(noseed.find("seed:"),
               noseed.find('\n', noseed.find("seed:")) - noseed.find("seed:") + 1);
  EXPECT_NE(errorOf(noseed).find("seed: missing"), std::string::npos) << errorOf(noseed);
  // An unknown field is a typo, not silently ignored.
  EXPECT_NE(errorOf(good + "extra: 1\n").find("extra: unknown key"), std::string::npos);
}

TEST(WeightsIo, RegimesRoundTripAndVersionOneStillLoads) {
  LearnedState s = PreadaptNetwork(3, 3, 5, 1.0).state();
  for (int k = 0; k < 3; ++k) {
    RegimeEntry e;
    e.theta = Vec::Constant(3, 0.1 + 1.0 / 3.0 * k);
    e.theta[1] = -2.5 * k;
    e.uses = k + 1;
    e.last_used = 10 * k;
    e.loss = 0.1 * k + 1.0 / 7.0;
    e.loss_info = 3.5 * k + 0.5;
    s.regimes.push_back(e);
  }
  const std::string dir = tmpDir();
  saveWeights(dir + "/w.yaml", s);
  const LearnedState back = loadWeights(dir + "/w.yaml", 3, 3);
  ASSERT_EQ(back.regimes.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ((back.regimes[k].theta - s.regimes[k].theta).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(back.regimes[k].uses, s.regimes[k].uses);
    EXPECT_EQ(back.regimes[k].last_used, s.regimes[k].last_used);
    EXPECT_EQ(back.regimes[k].loss, s.regimes[k].loss);
    EXPECT_EQ(back.regimes[k].loss_info, s.regimes[k].loss_info);
  }
  // A version 2 file (regimes without a loss) loads with no loss identified; in it the
  // version 3 keys are unknown.
  std::string v2 = weightsToYaml(s);
  v2.replace(v2.find("version: 3"), 10, "version: 2");
  EXPECT_NE(errorOf(v2).find("regimes.0.loss: unknown key"), std::string::npos) << errorOf(v2);
  std::string v2_clean;
  std::istringstream lines(v2);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("    loss", 0) != 0) v2_clean += line + "\n";
  EXPECT_EQ(errorOf(v2_clean), "no error");
  const LearnedState old = parseWeights(v2_clean, "w2.yaml", 3, 3);
  ASSERT_EQ(old.regimes.size(), 3u);
  EXPECT_EQ(old.regimes[2].loss, 0.0);
  EXPECT_EQ(old.regimes[2].loss_info, 0.0);
  // A version 1 file (no regimes) loads with an empty memory.
  std::string v1 = weightsToYaml(PreadaptNetwork(3, 3, 5, 1.0).state());
  v1.replace(v1.find("version: 3"), 10, "version: 1");
  v1.erase(v1.find("regimes:"));
  EXPECT_EQ(errorOf(v1), "no error");
  EXPECT_TRUE(parseWeights(v1, "w1.yaml", 3, 3).regimes.empty());
  // Version 2 without regimes, a regime of the wrong size, NaN, a typo: each named.
  std::string noreg = v1;
  noreg.replace(noreg.find("version: 1"), 10, "version: 2");
  EXPECT_NE(errorOf(noreg).find("regimes: missing"), std::string::npos) << errorOf(noreg);
  const std::string good = weightsToYaml(s);
  std::string small = good;
  small.replace(small.find("theta: [") + 8, 0, "7, ");
  EXPECT_NE(errorOf(small).find("regimes.0.theta"), std::string::npos) << errorOf(small);
  std::string nan = good;
  const size_t first = nan.find("theta: [") + 8;
  nan.replace(first, nan.find(',', first) - first, ".nan");
  EXPECT_NE(errorOf(nan).find("regimes.0.theta"), std::string::npos) << errorOf(nan);
  std::string typo = good;
  typo.replace(typo.find("    uses:"), 9, "    usez:");
  EXPECT_NE(errorOf(typo).find("regimes.0.usez: unknown key"), std::string::npos) << errorOf(typo);
  std::string neg = good;
  neg.replace(neg.find("uses: 1"), 7, "uses: -1");
  EXPECT_NE(errorOf(neg).find("regimes.0.uses"), std::string::npos) << errorOf(neg);
  // A loss that is not a number, an information below 0: each named.
  auto withLine = [&](const std::string& prefix, const std::string& line) {
    std::string t = good;
    const size_t at = t.find(prefix);
    t.replace(at, t.find('\n', at) - at, line);
    return t;
  };
  const std::string nan_loss = withLine("    loss: ", "    loss: .nan");
  EXPECT_NE(errorOf(nan_loss).find("regimes.0.loss"), std::string::npos) << errorOf(nan_loss);
  const std::string neg_info = withLine("    loss_info: ", "    loss_info: -1");
  EXPECT_NE(errorOf(neg_info).find("regimes.0.loss_info"), std::string::npos) << errorOf(neg_info);
}

TEST(WeightsIo, MismatchedSizesAreClearErrors) {
  const std::string h4 = weightsToYaml(PreadaptNetwork(4, 3, 1, 1.0).state());
  const std::string err = errorOf(h4, 3, 3);
  EXPECT_NE(err.find("hidden=4"), std::string::npos) << err;
  EXPECT_NE(err.find("needs hidden=3"), std::string::npos) << err;
  EXPECT_NE(errorOf(weightsToYaml(PreadaptNetwork(3, 2, 1, 1.0).state()), 3, 3).find("outputs=2"),
            std::string::npos);
  // Declared sizes that disagree with the matrices.
  std::string lie = weightsToYaml(PreadaptNetwork(3, 3, 1, 1.0).state());
  lie.replace(lie.find("hidden: 3"), 9, "hidden: 2");
  EXPECT_NE(errorOf(lie, -1, -1).find("V"), std::string::npos) << errorOf(lie, -1, -1);
}

TEST(WeightsIo, MissingAndEmptyFiles) {
  const std::string dir = tmpDir();
  EXPECT_THROW(loadWeights(dir + "/nope.yaml"), WeightsError);
  writeFile(dir + "/empty.yaml", "");
  try {
    loadWeights(dir + "/empty.yaml");
    FAIL() << "empty file accepted";
  } catch (const WeightsError& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos);
  }
}

TEST(WeightsIo, FailedSaveKeepsTheLastGoodFile) {
  const std::string dir = tmpDir();
  const std::string path = dir + "/w.yaml";
  saveWeights(path, PreadaptNetwork(3, 3, 1, 1.0).state());
  const std::string before = readFile(path);
  // Target is a non-empty directory: the rename must fail and leave no temporary behind.
  const std::string blocker = dir + "/blocked.yaml";
  ASSERT_EQ(mkdir(blocker.c_str(), 0755), 0);
  writeFile(blocker + "/keep", "x");
  EXPECT_THROW(saveWeights(blocker, PreadaptNetwork(3, 3, 2, 1.0).state()), WeightsError);
  // Directory without write permission is not usable as root; a missing directory is.
  EXPECT_THROW(saveWeights(dir + "/missing/w.yaml", PreadaptNetwork(3, 3, 2, 1.0).state()),
               WeightsError);
  EXPECT_EQ(readFile(path), before);
  int entries = 0;
  FILE* ls = popen(("ls -A " + dir).c_str(), "r");
  char buf[256];
  while (fgets(buf, sizeof(buf), ls)) {
    ++entries;
    EXPECT_EQ(std::string(buf).find(".tmp."), std::string::npos) << buf;
  }
  pclose(ls);
  EXPECT_EQ(entries, 2);  // w.yaml and blocked.yaml
}
