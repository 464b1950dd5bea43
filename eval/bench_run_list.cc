#include "eval/bench_run_list.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/text_format.h"
#include "eval/explore_runner.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;

constexpr const char* kComment =
    "# aslam bench run list: `aslam bench-task FILE N` runs the Nth run below (0-based)";
constexpr const char* kHeader = "dir\tworld\tmethod\tseed\tduration_s\tconfig\tstart";
constexpr int kFields = 7;

std::string Absolute(const std::string& path) {
  return path.empty() ? path : fs::absolute(path).lexically_normal().string();
}

std::string FormatStart(const std::optional<Pose2d>& start) {
  if (!start) return "";
  return Format("%.17g,%.17g,%.17g", start->x_m, start->y_m, start->yaw_rad);
}

std::vector<std::string> SplitTabs(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t tab = line.find('\t', begin);
    fields.push_back(line.substr(begin, tab - begin));
    if (tab == std::string::npos) return fields;
    begin = tab + 1;
  }
}

std::string Hostname() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "?";
  return name;
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

// True when descriptors a and b are the same file (a local bench's child already writes to
// explore.log).
bool SameFile(int a, int b) {
  struct stat sa {
  }, sb{};
  return fstat(a, &sa) == 0 && fstat(b, &sb) == 0 && sa.st_dev == sb.st_dev &&
         sa.st_ino == sb.st_ino;
}

}  // namespace

RunListEntry MakeRunListEntry(const BenchOptions& options, const BenchRun& run) {
  return {Absolute(run.dir),  Absolute(run.world),       run.method,   run.seed,
          options.duration_s, Absolute(run.config_file), options.start};
}

void WriteRunList(const std::string& path, const std::vector<RunListEntry>& entries) {
  std::string text = std::string(kComment) + "\n" + kHeader + "\n";
  for (const RunListEntry& e : entries) {
    const std::vector<std::pair<const char*, std::string>> fields = {
        {"dir", e.dir},
        {"world", e.world},
        {"method", e.method},
        {"seed", std::to_string(e.seed)},
        {"duration_s", Format("%.17g", e.duration_s)},
        {"config", e.config_file},
        {"start", FormatStart(e.start)}};
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const auto& [name, value] = fields[i];
      if (value.find_first_of("\t\n\r") != std::string::npos) {
        throw std::invalid_argument(std::string("run list ") + path + ": the " + name + " '" +
                                    value + "' holds a tab or a newline");
      }
      text += value + (i + 1 < fields.size() ? "\t" : "\n");
    }
  }
  fs::create_directories(fs::path(path).parent_path());
  WriteFileAtomically(path, text);
}

std::vector<RunListEntry> ReadRunList(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("run list " + path + ": " + std::strerror(errno));
  std::vector<RunListEntry> entries;
  std::string line;
  bool header = false;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = path + ":" + std::to_string(number) + ": ";
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      if (line != kHeader)
        throw std::runtime_error(where + "expected the header '" + std::string(kHeader) + "'");
      header = true;
      continue;
    }
    const std::vector<std::string> f = SplitTabs(line);
    if (static_cast<int>(f.size()) != kFields) {
      throw std::runtime_error(where + "expected " + std::to_string(kFields) +
                               " tab-separated fields, got " + std::to_string(f.size()));
    }
    RunListEntry entry;
    entry.dir = f[0];
    entry.world = f[1];
    entry.method = f[2];
    entry.config_file = f[5];
    try {
      ParseExploreMethod(entry.method, "method");
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(where + e.what());
    }
    char* end = nullptr;
    const long seed = std::strtol(f[3].c_str(), &end, 10);
    if (f[3].empty() || *end != '\0' || seed < 0)
      throw std::runtime_error(where + "seed '" + f[3] + "' is not a whole number >= 0");
    entry.seed = static_cast<int>(seed);
    entry.duration_s = std::strtod(f[4].c_str(), &end);
    if (f[4].empty() || *end != '\0')
      throw std::runtime_error(where + "duration_s '" + f[4] + "' is not a number");
    try {
      CheckDuration(entry.duration_s);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(where + e.what());
    }
    if (!f[6].empty()) {
      entry.start = ParsePose(f[6]);
      if (!entry.start) throw std::runtime_error(where + "start '" + f[6] + "': expected X,Y,YAW");
    }
    if (entry.dir.empty() || entry.world.empty())
      throw std::runtime_error(where + "dir and world must not be empty");
    entries.push_back(std::move(entry));
  }
  if (!header) throw std::runtime_error("run list " + path + ": no header line: not a run list");
  return entries;
}

std::vector<std::string> ExploreArgv(const std::string& aslam_binary, const RunListEntry& entry) {
  std::vector<std::string> args = {aslam_binary,
                                   "explore",
                                   "--inproc",
                                   "--world",
                                   entry.world,
                                   "--method",
                                   entry.method,
                                   "--seed",
                                   std::to_string(entry.seed),
                                   "--duration",
                                   Format("%.17g", entry.duration_s),
                                   "--out",
                                   entry.dir,
                                   "--progress",
                                   "60"};
  if (!entry.config_file.empty()) args.insert(args.end(), {"--config", entry.config_file});
  if (entry.start) args.insert(args.end(), {"--start", FormatStart(entry.start)});
  return args;
}

std::vector<std::string> BenchTaskArgv(const std::string& aslam_binary, const std::string& list,
                                       int index) {
  return {aslam_binary, "bench-task", list, std::to_string(index)};
}

int ExecBenchTask(const std::string& aslam_binary, const std::string& list,
                  const std::string& index) {
  try {
    const std::vector<RunListEntry> entries = ReadRunList(list);
    char* end = nullptr;
    const long n = std::strtol(index.c_str(), &end, 10);
    if (index.empty() || *end != '\0' || n < 0 || n >= static_cast<long>(entries.size())) {
      throw std::runtime_error("run list " + list + ": no run '" + index + "': it holds " +
                               std::to_string(entries.size()) + " runs, numbered from 0");
    }
    const RunListEntry& entry = entries[n];
    BenchRun run;
    run.dir = entry.dir;
    if (ReadFinishedRun(run)) {
      std::printf("aslam bench-task: run %ld (%s) has already finished: not run again\n", n,
                  entry.dir.c_str());
      return 0;
    }
    fs::create_directories(entry.dir);
    const std::string log_path = entry.dir + "/explore.log";
    const int log = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (log < 0) throw std::runtime_error(log_path + ": " + std::strerror(errno));
    const std::vector<std::string> argv = ExploreArgv(aslam_binary, entry);
    const std::string header =
        Format("=== aslam bench-task: run %ld of %s on %s at %s\n%s\n", n, list.c_str(),
               Hostname().c_str(), UtcNow().c_str(), ShellCommandLine(argv).c_str());
    if (!SameFile(log, STDOUT_FILENO)) {
      // A Slurm task's own log: which run, where its output goes.
      std::printf("%s(output in %s)\n", header.c_str(), log_path.c_str());
      std::fflush(stdout);
    }
    if (write(log, header.data(), header.size()) < 0 || dup2(log, STDOUT_FILENO) < 0 ||
        dup2(log, STDERR_FILENO) < 0) {
      throw std::runtime_error(log_path + ": " + std::strerror(errno));
    }
    std::vector<char*> args;
    for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
    args.push_back(nullptr);
    execv(aslam_binary.c_str(), args.data());
    throw std::runtime_error("cannot run " + aslam_binary + ": " + std::strerror(errno));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam bench-task: %s\n", e.what());
    return 1;
  }
}

}  // namespace aslam
