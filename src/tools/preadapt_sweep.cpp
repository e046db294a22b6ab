/// \file preadapt_sweep.cpp
/// \brief Many batch runs in parallel: seeds x modes x a grid of settings, one JSON line each.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <iostream>
#include <map>
#include <mutex>
#include <thread>

#include "cli_common.hpp"

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

}  // namespace

int main(int argc, char** argv) {
  try {
    cli::RunRequest base;
    std::vector<std::string> modes;
    std::vector<std::uint64_t> seeds;
    std::vector<Axis> axes;
    unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
    CLI::App app{
        "Runs the cartesian product of modes, seeds and every --grid axis on N threads (default: "
        "all cores) and prints one JSON line per run, in a fixed order, each with a \"grid\" "
        "object naming its settings and an \"index\". Exit code 2 on bad input. Example: "
        "preadapt_sweep --scenario 1 --modes rac,pa_learn --seeds 1-20 --grid "
        "controller.attention.c_e=0.003,0.005,0.01",
        "preadapt_sweep"};
    cli::RunOptionText text;
    std::string modes_text, seeds_text, jobs_text;
    std::vector<std::string> grids;
    cli::addRunOptions(app, &base, &text, true);
    cli::addText(app, "--modes", &modes_text, "comma-separated modes (rac, pa, pa_learn, ...)");
    cli::addText(app, "--mode", &modes_text, "the same as --modes");
    cli::addText(app, "--seeds", &seeds_text, "network seeds: 1-20 or 1,5,9");
    cli::addTexts(app, "--grid", &grids, "key=v1,v2,... (repeatable; the last axis runs fastest)");
    cli::addText(app, "--jobs", &jobs_text, "threads (default: all cores)");
    if (!cli::parseCommandLine(app, argc, argv)) return 0;
    if (app.count("--scenario") == 0)
      throw cli::UsageError("--scenario is required (1, 2, 3 or a YAML path)");
    cli::finishRunOptions(text, &base);
    if (!modes_text.empty())
      for (const auto& m : cli::splitTopLevel(modes_text)) {
        if (!parseMode(m))
          throw cli::UsageError("--modes: unknown mode '" + m +
                                "' (expected rac, pa, pa_learn, pa_learn_exact, pa_robust or "
                                "oracle)");
        modes.push_back(m);
      }
    if (!seeds_text.empty()) seeds = parseSeeds(seeds_text);
    for (const auto& g : grids) {
      const auto eq = g.find('=');
      if (eq == std::string::npos || eq == 0 || eq + 1 == g.size())
        throw cli::UsageError("--grid '" + g + "': expected key=v1,v2,...");
      axes.push_back({g.substr(0, eq), cli::splitTopLevel(g.substr(eq + 1))});
    }
    if (!jobs_text.empty()) {
      const auto j = cli::parseSeed("--jobs", jobs_text);
      if (j < 1 || j > 1024) throw cli::UsageError("--jobs: expected 1..1024");
      jobs = static_cast<unsigned>(j);
    }

    // Build the run list: modes x seeds x grid (last axis fastest). Prepare (and so validate)
    // every run before starting any, so a bad grid value fails fast with exit code 2.
    struct Job {
      cli::PreparedRun run;
      std::vector<std::pair<std::string, std::string>> grid;
    };
    std::vector<Job> jobs_list;
    std::vector<std::optional<std::string>> mode_list;
    if (modes.empty()) mode_list.push_back(std::nullopt);
    for (const auto& m : modes) mode_list.push_back(m);
    std::vector<std::optional<std::uint64_t>> seed_list;
    if (seeds.empty()) seed_list.push_back(std::nullopt);
    for (auto s : seeds) seed_list.push_back(s);
    size_t grid_count = 1;
    for (const auto& ax : axes) grid_count *= ax.values.size();
    for (const auto& m : mode_list)
      for (const auto& s : seed_list)
        for (size_t g = 0; g < grid_count; ++g) {
          cli::RunRequest req = base;
          req.mode = m;
          req.seed = s;
          Job job;
          size_t rest = g;
          std::vector<std::string> extra;
          for (auto it = axes.rbegin(); it != axes.rend(); ++it) {
            const std::string& v = it->values[rest % it->values.size()];
            rest /= it->values.size();
            job.grid.insert(job.grid.begin(), {it->key, v});
          }
          for (const auto& kv : job.grid) req.sets.push_back(kv.first + "=" + kv.second);
          job.run = cli::prepare(req);
          jobs_list.push_back(std::move(job));
        }

    std::vector<std::string> lines(jobs_list.size());
    std::vector<char> ready(jobs_list.size(), 0);
    std::atomic<size_t> next{0};
    std::mutex mu;
    std::condition_variable cv;
    std::string failure;
    auto worker = [&] {
      for (;;) {
        const size_t i = next.fetch_add(1);
        if (i >= jobs_list.size()) return;
        Job& job = jobs_list[i];
        std::string line;
        try {
          const auto t0 = std::chrono::steady_clock::now();
          std::unique_ptr<Controller> ctl;
          SimResult res = cli::execute(job.run, false, &ctl);
          job.run.info.wall_time_s =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          nlohmann::ordered_json out;
          out["index"] = i;
          out["grid"] = nlohmann::ordered_json::object();
          for (const auto& kv : job.grid) out["grid"][kv.first] = kv.second;
          // Named: items() of a temporary would dangle (the summary dies before the loop runs).
          const nlohmann::ordered_json summary = runSummary(job.run.info, *ctl, res);
          for (const auto& kv : summary.items()) out[kv.key()] = kv.value();
          line = out.dump();
        } catch (const std::exception& e) {
          std::lock_guard<std::mutex> lk(mu);
          if (failure.empty()) failure = "run " + std::to_string(i) + ": " + e.what();
        }
        {
          std::lock_guard<std::mutex> lk(mu);
          lines[i] = std::move(line);
          ready[i] = 1;
        }
        cv.notify_all();
      }
    };
    std::vector<std::thread> pool;
    const unsigned n_threads = std::min<unsigned>(jobs, static_cast<unsigned>(jobs_list.size()));
    for (unsigned t = 0; t < n_threads; ++t) pool.emplace_back(worker);
    // Print in index order as runs complete, so output streams and stays deterministic.
    for (size_t i = 0; i < jobs_list.size(); ++i) {
      std::unique_lock<std::mutex> lk(mu);
      cv.wait(lk, [&] { return ready[i] != 0; });
      if (!lines[i].empty()) std::cout << lines[i] << '\n' << std::flush;
    }
    for (auto& t : pool) t.join();
    if (!failure.empty()) {
      std::cerr << "preadapt_sweep: error: " << failure << std::endl;
      return 1;
    }
    return 0;
  } catch (const cli::UsageError& e) {
    std::cerr << "preadapt_sweep: error: " << e.what() << std::endl;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "preadapt_sweep: error: " << e.what() << std::endl;
    return 1;
  }
}
