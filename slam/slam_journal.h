#pragma once

// SLAM's journal (docs/architecture.md §4): an append-only file of what the graph and the
// map are made of, written as the graph grows, so that aslam-slam resumes after a crash
// with the same "map" frame and keyframe ids, and a finished exploration can be continued
// later (--resume). Each keyframe with its scan, odometry and sequential edge; each loop
// closure added or removed; the poses after each optimization; the front end's state.
//
// File: the 8 bytes "ASLAMJ01", then records [u32 type][u32 length][payload][u32 CRC-32
// of type, length and payload], little-endian. A record cut short or damaged (a crash
// mid-write) ends what is read; the writer cuts the file there before appending again.

#include <cstdint>
#include <optional>
#include <string>

#include "slam/slam.h"

namespace aslam {

struct SlamJournalRead {
  SlamSnapshot snapshot;
  int64_t records = 0;
  int64_t valid_bytes = 0;  // the file's length up to the last whole record
  // Set when bytes after valid_bytes could not be read: why, and where.
  std::optional<std::string> damage;
};

// Reads the journal at `path` and replays it into the Slam it describes. Throws
// std::runtime_error naming the path when the file cannot be read or is not a journal.
SlamJournalRead ReadSlamJournal(const std::string& path);

// Appends to a journal. Never throws once open: the first write error stops journaling and
// is kept in error() (SLAM goes on; the process reports it).
class SlamJournalWriter final : public SlamJournalSink {
 public:
  // Opens `path`, creating it (with its header) or cutting it to `valid_bytes` (from
  // ReadSlamJournal) so new records follow the last whole one. Throws std::runtime_error
  // naming the path on failure.
  SlamJournalWriter(const std::string& path, int64_t valid_bytes, double sync_period_s = 1.0);
  ~SlamJournalWriter() override;
  SlamJournalWriter(const SlamJournalWriter&) = delete;
  SlamJournalWriter& operator=(const SlamJournalWriter&) = delete;

  void OnKeyframe(const KeyframeRecord& keyframe,
                  const std::optional<PoseGraphEdge>& sequential_edge) override;
  void OnLoopClosureAdded(const PoseGraphEdge& edge) override;
  void OnEdgeRemoved(const PoseGraphEdge& edge) override;
  void OnOptimized(const std::vector<PoseGraphNode>& nodes) override;
  void OnState(const SlamState& state) override;

  // Hands what was appended to the kernel (it then survives the process being killed), and
  // syncs it to disk when sync_period_s of message time passed since the last sync.
  void Commit(int64_t utime);
  // Writes and syncs everything now.
  void Sync();

  // Every optimization appends all poses, so a long session's journal grows with keyframes x
  // closures. True once those records are more than half of the journal (and it is over
  // 1 MiB): then Rewrite keeps it within about twice what the graph itself needs.
  bool WantsRewrite() const;
  // Replaces the journal with one holding `snapshot` alone (edges in the graph's order, each
  // keyframe at its current pose): the same Slam when read back. Written with
  // WriteFileAtomically, so a crash leaves the old journal or the new one, whole. On failure
  // (returned, with why) the old journal stays and appending goes on there.
  bool Rewrite(const SlamSnapshot& snapshot, std::string* why_not);
  int64_t rewrites() const { return rewrites_; }

  const std::string& path() const { return path_; }
  const std::optional<std::string>& error() const { return error_; }
  int64_t bytes_written() const { return bytes_written_; }

 private:
  void Append(uint32_t type, const std::string& payload);
  void Fail(const std::string& what);

  std::string path_;
  int fd_ = -1;
  int64_t sync_period_us_;
  int64_t last_sync_utime_ = 0;
  std::string pending_;
  int64_t bytes_written_ = 0;
  int64_t pose_bytes_written_ = 0;  // in optimized-pose records, since the last rewrite
  int64_t rewrites_ = 0;
  std::optional<std::string> error_;
};

}  // namespace aslam
