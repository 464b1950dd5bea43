#include "slam/slam_process.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>

#include "common/lcm_util.h"
#include "slam/slam_config.h"
#include "slam/slam_node.h"

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};
std::atomic<bool> g_save{false};

// Failing to save is reported, not fatal: SLAM keeps running (or exits cleanly).
void Save(SlamNode& node, const std::string& out_dir) {
  if (out_dir.empty()) {
    std::printf("aslam-slam: no --out-dir, nothing written\n");
    return;
  }
  try {
    const bool map_written = node.WriteOutputs(out_dir);
    std::printf("aslam-slam: wrote %s/graph.g2o (%zu keyframes)%s\n", out_dir.c_str(),
                node.slam().graph().nodes.size(),
                map_written ? " and map.yaml + map.pgm" : "; no map yet");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-slam: writing outputs failed: %s\n", e.what());
  }
  std::fflush(stdout);
}

constexpr char kJournalFile[] = "/slam.journal";

// Reads a journal, printing what it holds and any damage at its end.
SlamJournalRead ReadJournalVerbosely(const std::string& path) {
  SlamJournalRead read = ReadSlamJournal(path);
  std::printf("aslam-slam: %s: %zu keyframes, %zu edges\n", path.c_str(),
              read.snapshot.graph.nodes.size(), read.snapshot.graph.edges.size());
  if (read.damage) {
    std::fprintf(stderr, "aslam-slam: warning: %s: %s (cut there before appending)\n", path.c_str(),
                 read.damage->c_str());
  }
  return read;
}

// Where SLAM starts from: the journal of a restart, else --resume, else nothing.
// Opens the journal writer when there is a journal folder.
std::optional<SlamJournalRead> StartingPoint(const SlamProcessOptions& options,
                                             std::unique_ptr<SlamJournalWriter>* writer) {
  const std::string journal = options.journal_dir.empty() ? "" : options.journal_dir + kJournalFile;
  std::optional<SlamJournalRead> start;
  if (!journal.empty() && std::filesystem::exists(journal)) {
    std::printf("aslam-slam: resuming from its own journal (a restart)\n");
    start = ReadJournalVerbosely(journal);
  } else if (!options.resume_dir.empty()) {
    const std::string source = options.resume_dir + kJournalFile;
    std::printf("aslam-slam: continuing from %s\n", source.c_str());
    start = ReadJournalVerbosely(source);
    if (!journal.empty()) {
      std::filesystem::create_directories(options.journal_dir);
      std::filesystem::copy_file(source, journal);
    }
  }
  if (!journal.empty()) {
    std::filesystem::create_directories(options.journal_dir);
    *writer = std::make_unique<SlamJournalWriter>(journal, start ? start->valid_bytes : 0);
  }
  return start;
}

}  // namespace

int RunSlamProcess(const SlamProcessOptions& options) {
  try {
    const SlamConfig config = LoadSlamConfigFromFile(options.config_file);
    const std::string url = ResolveLcmUrl(options.lcm_url);
    const auto lcm = OpenLcm(url);
    SlamNode node(*lcm, config.slam, config.node);
    std::unique_ptr<SlamJournalWriter> journal;
    if (std::optional<SlamJournalRead> start = StartingPoint(options, &journal)) {
      node.Resume(std::move(start->snapshot));
    }
    node.set_journal(journal.get());

    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    std::signal(SIGUSR1, [](int) { g_save = true; });
    std::printf("aslam-slam: on %s, config %s, outputs %s, journal %s\n", url.c_str(),
                options.config_file.empty() ? "(defaults)" : options.config_file.c_str(),
                options.out_dir.empty() ? "(none)" : options.out_dir.c_str(),
                journal ? journal->path().c_str() : "(none)");
    std::fflush(stdout);

    bool journal_error_reported = false;
    // The timeout bounds how long a signal waits to be noticed.
    while (!g_stop.load()) {
      // A signal interrupts the wait with an error; only a failure without one is real.
      if (lcm->handleTimeout(100) < 0 && !g_stop.load() && !g_save.load() && errno != EINTR) {
        std::fprintf(stderr, "aslam-slam: LCM receive failed: %s\n", std::strerror(errno));
        Save(node, options.out_dir);
        return 1;
      }
      if (g_save.exchange(false)) Save(node, options.out_dir);
      if (journal && journal->error() && !journal_error_reported) {
        std::fprintf(stderr, "aslam-slam: %s\n", journal->error()->c_str());
        journal_error_reported = true;
      }
    }
    Save(node, options.out_dir);
    if (journal) journal->Sync();
    std::printf("aslam-slam: stopped\n%s", node.CountersReport().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-slam: %s\n", e.what());
    return 1;
  }
}

}  // namespace aslam
