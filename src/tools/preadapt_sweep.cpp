/// \file preadapt_sweep.cpp
/// \brief Many batch runs in parallel: seeds x modes x a grid of settings, one JSON line each.
/// --shard K/N runs one of N disjoint slices of the same run list (one per machine or cluster
/// task); --merge combines the slices' outputs into the output of the unsharded sweep.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <thread>

#include "cli_common.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"

using namespace preadaptive_mrac;

namespace {
std::vector<std::uint64_t> parseSeeds(const std::string& text) {
  std::vector<std::uint64_t> out;
  for (const auto& part : cli::splitTopLevel(text)) {
    const auto dash = part.find('-');
    if (dash != std::string::npos && dash > 0) {
      const auto a = cli::parseSeed("--seeds", part.substr(0, dash));
      const auto b = cli::parseSeed("--seeds", part.substr(dash + 1));
      if (b < a) throw cli::UsageError("--seeds: empty range '" + part + "'");
      if (b - a > 1000000) throw cli::UsageError("--seeds: range too large '" + part + "'");
      for (auto s = a; s <= b; ++s) out.push_back(s);
    } else {
      out.push_back(cli::parseSeed("--seeds", part));
    }
  }
  return out;
}

struct Axis {
  std::string key;
  std::vector<std::string> values;
};

struct Shard {
  std::uint64_t k = 0;  ///< 0-based
  std::uint64_t n = 1;
};

Shard parseShard(const std::string& text) {
  const auto slash = text.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == text.size())
    throw cli::UsageError("--shard '" + text + "': expected K/N, e.g. 0/4 (K is 0-based)");
  Shard sh;
  sh.k = cli::parseSeed("--shard", text.substr(0, slash));
  sh.n = cli::parseSeed("--shard", text.substr(slash + 1));
  if (sh.n < 1) throw cli::UsageError("--shard '" + text + "': N must be >= 1");
  if (sh.k >= sh.n)
    throw cli::UsageError("--shard '" + text + "': K must be in 0.." + std::to_string(sh.n - 1) +
                          " (K is 0-based)");
  return sh;
}

/// One run of the list as the merge checks it against a shard's line.
struct Expected {
  std::string mode;
  std::uint64_t seed;
  std::vector<std::pair<std::string, std::string>> grid;
};

/// Read the shards' outputs, check that together they hold every run of the list exactly once
/// (each line's index, mode, seed and grid as the list says) and print the lines in index
/// order, byte for byte as the shards wrote them. Throws MergeError naming the file and line.
class MergeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void mergeShards(const std::vector<std::string>& files, const std::vector<Expected>& expected) {
  std::vector<std::string> lines(expected.size());
  std::vector<std::string> where(expected.size());
  for (const auto& f : files) {
    std::ifstream in(f);
    if (!in) throw MergeError(f + ": cannot open");
    std::string line;
    size_t no = 0;
    while (std::getline(in, line)) {
      ++no;
      const std::string at = f + ":" + std::to_string(no);
      if (line.empty()) throw MergeError(at + ": empty line");
      nlohmann::json j;
      try {
        j = nlohmann::json::parse(line);
      } catch (const std::exception&) {
        throw MergeError(at + ": not a JSON line of preadapt_sweep (truncated output?)");
      }
      if (!j.is_object() || !j.contains("index") || !j["index"].is_number_unsigned())
        throw MergeError(at + ": no 'index' field");
      const auto i = j["index"].get<std::uint64_t>();
      if (i >= expected.size())
        throw MergeError(at + ": index " + std::to_string(i) + " is outside this sweep's " +
                         std::to_string(expected.size()) + " runs (other sweep options?)");
      const Expected& e = expected[i];
      bool same = j.value("mode", std::string()) == e.mode && j.contains("seed") &&
                  j["seed"].is_number_unsigned() && j["seed"].get<std::uint64_t>() == e.seed &&
                  j.contains("grid") && j["grid"].is_object() && j["grid"].size() == e.grid.size();
      for (const auto& kv : e.grid)
        same = same && j["grid"].contains(kv.first) && j["grid"][kv.first] == kv.second;
      if (!same)
        throw MergeError(at + ": run " + std::to_string(i) +
                         " has another mode, seed or grid than this sweep's run " +
                         std::to_string(i) + " (other sweep options?)");
      if (!lines[i].empty())
        throw MergeError(at + ": run " + std::to_string(i) + " again (also in " + where[i] + ")");
      lines[i] = line;
      where[i] = at;
    }
  }
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i].empty())
      throw MergeError("run " + std::to_string(i) + " of " + std::to_string(lines.size()) +
                       " is in none of the " + std::to_string(files.size()) +
                       " files (a shard missing, failed or cut short?)");
  for (const auto& l : lines) std::cout << l << '\n';
  std::cout << std::flush;
}

// What the command line asks for, checked.
struct Options {
  cli::RunRequest base;
  std::vector<std::string> modes;
  std::vector<std::uint64_t> seeds;
  std::vector<Axis> axes;
  unsigned jobs = 1;
  std::optional<Shard> shard;
  std::vector<std::string> merge_files;
  bool no_wall_time = false;
};

// Parse and check the command line; false after printing --help. Throws cli::UsageError.
bool parseOptions(int argc, char** argv, Options* opt) {
  opt->jobs = std::max(1u, std::thread::hardware_concurrency());
  CLI::App app{
      "Runs the cartesian product of modes, seeds and every --grid axis on N threads (default: "
      "all cores) and prints one JSON line per run, in a fixed order, each with a \"grid\" "
      "object naming its settings and an \"index\". Exit code 2 on bad input. Example: "
      "preadapt_sweep --scenario 1 --modes rac,pa_learn --seeds 1-20 --grid "
      "controller.attention.c_e=0.003,0.005,0.01\n\nOn many machines: run the same command "
      "with --shard K/N for K = 0..N-1 (one process each, anywhere), then the same command "
      "with --merge and the N outputs: it prints what the unsharded sweep prints (byte for "
      "byte with --no-wall-time). Exit code 1 when a run fails or the merge finds a run "
      "missing, repeated or foreign.",
      "preadapt_sweep"};
  cli::RunOptionText text;
  std::string modes_text, seeds_text, jobs_text;
  std::vector<std::string> grids;
  cli::addRunOptions(app, &opt->base, &text, true);
  cli::addText(app, "--modes", &modes_text, "comma-separated modes: " + modeNames(", "));
  cli::addText(app, "--mode", &modes_text, "the same as --modes");
  cli::addText(app, "--seeds", &seeds_text, "network seeds: 1-20 or 1,5,9");
  cli::addTexts(app, "--grid", &grids, "key=v1,v2,... (repeatable; the last axis runs fastest)");
  cli::addText(app, "--jobs", &jobs_text, "threads (default: all cores)");
  std::string shard_text;
  cli::addText(app, "--shard", &shard_text,
               "K/N: run only the runs whose index i has i mod N = K; K is 0-based (0..N-1), "
               "so --shard 0/4 .. --shard 3/4 run the whole list once; lines keep their "
               "index in the whole list");
  app.add_option("--merge", opt->merge_files,
                 "FILE...: run nothing; read the outputs of the N shards (any order; give the "
                 "same sweep options as the shards) and print the unsharded output")
      ->expected(-1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->type_name("FILE");
  app.add_flag("--no-wall-time", opt->no_wall_time,
               "leave wall_time_s out of each line, so the same sweep gives the same bytes");
  if (!cli::parseCommandLine(app, argc, argv)) return false;
  if (!shard_text.empty()) opt->shard = parseShard(shard_text);
  if (opt->shard && !opt->merge_files.empty())
    throw cli::UsageError("--shard and --merge: give one of them (--merge reads every shard)");
  if (app.count("--scenario") == 0)
    throw cli::UsageError("--scenario is required (1, 2, 3 or a YAML path)");
  cli::finishRunOptions(text, &opt->base);
  if (!modes_text.empty())
    for (const auto& m : cli::splitTopLevel(modes_text)) {
      if (findMode(m) == nullptr)
        throw cli::UsageError("--modes: unknown mode '" + m + "' (expected " +
                              modeNames(", ", " or ") + ")");
      opt->modes.push_back(m);
    }
  if (!seeds_text.empty()) opt->seeds = parseSeeds(seeds_text);
  for (const auto& g : grids) {
    const auto eq = g.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == g.size())
      throw cli::UsageError("--grid '" + g + "': expected key=v1,v2,...");
    opt->axes.push_back({g.substr(0, eq), cli::splitTopLevel(g.substr(eq + 1))});
  }
  if (!jobs_text.empty())
    opt->jobs = static_cast<unsigned>(cli::parseCount("--jobs", jobs_text, 1024));
  return true;
}

// One run of the list: the prepared run and its grid settings.
struct Job {
  cli::PreparedRun run;
  std::vector<std::pair<std::string, std::string>> grid;
};

// The run list: modes x seeds x grid (last axis fastest). Every run is prepared (and so
// validated) before any starts, so a bad grid value fails fast with exit code 2.
std::vector<Job> buildRuns(const Options& opt) {
  std::vector<Job> jobs;
  std::vector<std::optional<std::string>> mode_list;
  if (opt.modes.empty()) mode_list.push_back(std::nullopt);
  for (const auto& m : opt.modes) mode_list.push_back(m);
  std::vector<std::optional<std::uint64_t>> seed_list;
  if (opt.seeds.empty()) seed_list.push_back(std::nullopt);
  for (auto s : opt.seeds) seed_list.push_back(s);
  size_t grid_count = 1;
  for (const auto& ax : opt.axes) grid_count *= ax.values.size();
  for (const auto& m : mode_list)
    for (const auto& s : seed_list)
      for (size_t g = 0; g < grid_count; ++g) {
        cli::RunRequest req = opt.base;
        req.mode = m;
        req.seed = s;
        Job job;
        size_t rest = g;
        for (auto it = opt.axes.rbegin(); it != opt.axes.rend(); ++it) {
          const std::string& v = it->values[rest % it->values.size()];
          rest /= it->values.size();
          job.grid.insert(job.grid.begin(), {it->key, v});
        }
        for (const auto& kv : job.grid) req.sets.push_back(kv.first + "=" + kv.second);
        job.run = cli::prepare(req);
        jobs.push_back(std::move(job));
      }
  return jobs;
}

// --merge: the shards' outputs checked against the run list and printed as one.
int merge(const Options& opt, const std::vector<Job>& jobs) {
  std::vector<Expected> expected;
  for (const auto& job : jobs) expected.push_back({job.run.info.mode, job.run.info.seed, job.grid});
  try {
    mergeShards(opt.merge_files, expected);
  } catch (const MergeError& e) {
    std::cerr << "preadapt_sweep: error: --merge: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}

// Run `i` of the list: its JSON line (index, grid, then the run's summary).
std::string runOne(const Options& opt, size_t i, Job* job, SimResult* res) {
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_ptr<Controller> ctl;
  *res = cli::execute(job->run, false, &ctl);
  job->run.info.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  nlohmann::ordered_json out;
  out["index"] = i;
  out["grid"] = nlohmann::ordered_json::object();
  for (const auto& kv : job->grid) out["grid"][kv.first] = kv.second;
  // A named summary: items() of a temporary would refer to it after its end (it crashed here).
  const auto summary = runSummary(job->run.info, *ctl, *res);
  for (const auto& kv : summary.items())
    if (!(opt.no_wall_time && kv.key() == "wall_time_s")) out[kv.key()] = kv.value();
  return out.dump();
}

// This shard's runs (all without --shard) on opt.jobs threads, their lines printed in index
// order as they complete, then the runs that left the flight envelope on stderr.
int runSweep(const Options& opt, std::vector<Job>* jobs) {
  // This shard's runs, by their index in the whole list.
  std::vector<size_t> mine;
  for (size_t i = 0; i < jobs->size(); ++i)
    if (!opt.shard || i % opt.shard->n == opt.shard->k) mine.push_back(i);
  std::vector<std::string> lines(mine.size());
  std::vector<char> ready(mine.size(), 0);
  std::atomic<size_t> next{0};
  std::mutex mu;
  std::condition_variable cv;
  std::string failure;
  std::vector<std::pair<size_t, std::string>> exits;  // runs that left the envelope
  auto worker = [&] {
    for (;;) {
      const size_t slot = next.fetch_add(1);
      if (slot >= mine.size()) return;
      const size_t i = mine[slot];
      Job& job = (*jobs)[i];
      std::string line;
      try {
        SimResult res;
        line = runOne(opt, i, &job, &res);
        if (res.envelope_exit.exited) {
          std::lock_guard<std::mutex> lk(mu);
          exits.emplace_back(i, "run " + std::to_string(i) + " (mode " + job.run.info.mode +
                                    ", seed " + std::to_string(job.run.info.seed) +
                                    "): " + cli::envelopeNote(res.envelope_exit));
        }
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lk(mu);
        if (failure.empty()) failure = "run " + std::to_string(i) + ": " + e.what();
      }
      {
        std::lock_guard<std::mutex> lk(mu);
        lines[slot] = std::move(line);
        ready[slot] = 1;
      }
      cv.notify_all();
    }
  };
  std::vector<std::thread> pool;
  const unsigned n_threads = std::min<unsigned>(opt.jobs, static_cast<unsigned>(mine.size()));
  for (unsigned t = 0; t < n_threads; ++t) pool.emplace_back(worker);
  // Print in index order as runs complete, so output streams and stays deterministic.
  for (size_t i = 0; i < mine.size(); ++i) {
    std::unique_lock<std::mutex> lk(mu);
    cv.wait(lk, [&] { return ready[i] != 0; });
    if (!lines[i].empty()) std::cout << lines[i] << '\n' << std::flush;
  }
  for (auto& t : pool) t.join();
  if (!failure.empty()) {
    std::cerr << "preadapt_sweep: error: " << failure << std::endl;
    return 1;
  }
  // The summary (stdout stays the JSON lines, whose envelope_exit says the same per run).
  if (!exits.empty()) {
    std::sort(exits.begin(), exits.end());
    std::cerr << "preadapt_sweep: " << exits.size() << " of " << mine.size()
              << " run(s) left the flight envelope:\n";
    for (const auto& e : exits) std::cerr << "  " << e.second << '\n';
    std::cerr << std::flush;
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return cli::runTool("preadapt_sweep", [&]() -> int {
    Options opt;
    if (!parseOptions(argc, argv, &opt)) return 0;
    std::vector<Job> jobs = buildRuns(opt);
    if (!opt.merge_files.empty()) return merge(opt, jobs);
    return runSweep(opt, &jobs);
  });
}
