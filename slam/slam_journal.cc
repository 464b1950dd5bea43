#include "slam/slam_journal.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "common/atomic_file.h"

namespace aslam {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the journal is written little-endian");

constexpr char kMagic[8] = {'A', 'S', 'L', 'A', 'M', 'J', '0', '2'};  // 02: beam times
constexpr std::size_t kRecordOverhead = 12;                           // type, length, CRC
constexpr uint32_t kMaxRecordBytes = 64u << 20;

enum RecordType : uint32_t {
  kKeyframe = 1,
  kLoopClosureAdded = 2,
  kEdgeRemoved = 3,
  kOptimized = 4,
  kState = 5,
};

class Encoder {
 public:
  template <typename T>
  void Put(T value) {
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void PutPose(const Pose2d& p) {
    Put(p.x_m);
    Put(p.y_m);
    Put(p.yaw_rad);
  }
  void PutEdge(const PoseGraphEdge& e) {
    Put<int32_t>(e.from_id);
    Put<int32_t>(e.to_id);
    Put<uint8_t>(static_cast<uint8_t>(e.kind));
    PutPose(e.measurement);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) Put(e.information(r, c));
    }
  }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

struct DecodeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Decoder {
 public:
  explicit Decoder(const std::string& bytes) : bytes_(bytes) {}
  template <typename T>
  T Get() {
    if (bytes_.size() - offset_ < sizeof(T)) throw DecodeError("record shorter than its fields");
    T value;
    std::memcpy(&value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }
  Pose2d GetPose() {
    Pose2d p;
    p.x_m = Get<double>();
    p.y_m = Get<double>();
    p.yaw_rad = Get<double>();
    return p;
  }
  PoseGraphEdge GetEdge() {
    PoseGraphEdge e;
    e.from_id = Get<int32_t>();
    e.to_id = Get<int32_t>();
    const uint8_t kind = Get<uint8_t>();
    if (kind > static_cast<uint8_t>(EdgeKind::kLoopClosure)) throw DecodeError("bad edge kind");
    e.kind = static_cast<EdgeKind>(kind);
    e.measurement = GetPose();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) e.information(r, c) = Get<double>();
    }
    return e;
  }
  void ExpectEnd() const {
    if (offset_ != bytes_.size()) throw DecodeError("record longer than its fields");
  }

 private:
  const std::string& bytes_;
  std::size_t offset_ = 0;
};

uint32_t Crc(uint32_t type, uint32_t length, const char* payload) {
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, reinterpret_cast<const Bytef*>(&type), sizeof(type));
  crc = crc32(crc, reinterpret_cast<const Bytef*>(&length), sizeof(length));
  return static_cast<uint32_t>(crc32(crc, reinterpret_cast<const Bytef*>(payload), length));
}

void PutCounters(Encoder* e, const SlamCounters& c) {
  for (const int64_t v : {c.odometry_received, c.scans_received, c.scans_processed, c.invalid_beams,
                          c.odometry_rebases, c.scan_clock_resyncs, c.matches_low_response,
                          c.keyframes_not_mapped, c.loop_closures_accepted,
                          c.loop_closures_rejected, c.loop_closures_removed, c.optimizations}) {
    e->Put(v);
  }
  e->Put<uint32_t>(static_cast<uint32_t>(c.dropped.size()));
  for (const int64_t v : c.dropped) e->Put(v);
}

SlamCounters GetCounters(Decoder* d) {
  SlamCounters c;
  for (int64_t* v : {&c.odometry_received, &c.scans_received, &c.scans_processed, &c.invalid_beams,
                     &c.odometry_rebases, &c.scan_clock_resyncs, &c.matches_low_response,
                     &c.keyframes_not_mapped, &c.loop_closures_accepted, &c.loop_closures_rejected,
                     &c.loop_closures_removed, &c.optimizations}) {
    *v = d->Get<int64_t>();
  }
  const uint32_t reasons = d->Get<uint32_t>();
  for (uint32_t i = 0; i < reasons; ++i) {
    const int64_t v = d->Get<int64_t>();
    if (i < c.dropped.size()) c.dropped[i] = v;  // reasons a newer build added are skipped
  }
  return c;
}

// Applies one record to the snapshot being rebuilt.
void Replay(uint32_t type, const std::string& payload, SlamSnapshot* s) {
  Decoder d(payload);
  switch (type) {
    case kKeyframe: {
      KeyframeRecord k;
      k.id = d.Get<int32_t>();
      if (k.id != static_cast<int>(s->keyframes.size())) {
        throw DecodeError("keyframe " + std::to_string(k.id) + " out of order");
      }
      k.utime = d.Get<int64_t>();
      k.odom_pose = d.GetPose();
      k.pose = d.GetPose();
      k.in_map = d.Get<uint8_t>() != 0;
      LidarScan& scan = k.scan;
      scan.utime = d.Get<int64_t>();
      scan.seq = d.Get<int64_t>();
      scan.sensor_pose = d.GetPose();
      scan.angle_min_rad = d.Get<double>();
      scan.angle_increment_rad = d.Get<double>();
      scan.range_min_m = d.Get<double>();
      scan.range_max_m = d.Get<double>();
      const uint32_t beams = d.Get<uint32_t>();
      if (beams > kMaxRecordBytes / sizeof(float)) throw DecodeError("implausible beam count");
      scan.range_m.resize(beams);
      for (float& r : scan.range_m) r = d.Get<float>();
      if (d.Get<uint8_t>() != 0) {
        scan.beam_time_s.resize(beams);
        for (float& t : scan.beam_time_s) t = d.Get<float>();
      }
      std::optional<PoseGraphEdge> edge;
      if (d.Get<uint8_t>() != 0) edge = d.GetEdge();
      d.ExpectEnd();
      if (edge) s->graph.edges.push_back(*edge);
      s->graph.nodes.push_back(PoseGraphNode{k.id, k.utime, k.pose});
      s->keyframes.push_back(std::move(k));
      return;
    }
    case kLoopClosureAdded: {
      const PoseGraphEdge edge = d.GetEdge();
      d.ExpectEnd();
      s->graph.edges.push_back(edge);
      return;
    }
    case kEdgeRemoved: {
      const PoseGraphEdge removed = d.GetEdge();
      d.ExpectEnd();
      auto& edges = s->graph.edges;
      const auto it = std::find_if(edges.begin(), edges.end(), [&](const PoseGraphEdge& e) {
        return e.from_id == removed.from_id && e.to_id == removed.to_id && e.kind == removed.kind &&
               e.measurement.x_m == removed.measurement.x_m &&
               e.measurement.y_m == removed.measurement.y_m &&
               e.measurement.yaw_rad == removed.measurement.yaw_rad;
      });
      if (it == edges.end()) throw DecodeError("removes an edge the journal never added");
      edges.erase(it);
      return;
    }
    case kOptimized: {
      const uint32_t n = d.Get<uint32_t>();
      if (n > s->graph.nodes.size()) throw DecodeError("poses for keyframes not yet added");
      std::vector<Pose2d> poses(n);
      for (Pose2d& pose : poses) pose = d.GetPose();
      d.ExpectEnd();
      for (uint32_t i = 0; i < n; ++i) s->graph.nodes[i].pose = poses[i];
      return;
    }
    case kState: {
      SlamState state;
      state.counters = GetCounters(&d);
      state.last_closure_attempt_node = d.Get<int32_t>();
      if (d.Get<uint8_t>() != 0) state.last_mapped_odom_pose = d.GetPose();
      state.odometry_correction = d.GetPose();
      d.ExpectEnd();
      s->state = state;
      return;
    }
    default: throw DecodeError("unknown record type " + std::to_string(type));
  }
}

std::string ErrnoText() { return std::strerror(errno); }

// write(2) until all of `bytes` is written; false (errno set) on the first failure.
bool WriteAll(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

SlamJournalRead ReadSlamJournal(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read SLAM journal " + path + ": " + ErrnoText());
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < sizeof(kMagic) || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    throw std::runtime_error(path +
                             ": not an aslam SLAM journal of this version (no ASLAMJ02 header; "
                             "ASLAMJ01 is an older aslam's)");
  }
  SlamJournalRead read;
  std::size_t offset = sizeof(kMagic);
  std::string payload;
  while (offset < bytes.size()) {
    const auto damaged = [&](const std::string& why) {
      read.damage = why + " at byte " + std::to_string(offset) + " of " +
                    std::to_string(bytes.size()) + "; " + std::to_string(read.records) +
                    " records before it are used";
    };
    if (bytes.size() - offset < kRecordOverhead) {
      damaged("a record cut short");
      break;
    }
    uint32_t type, length, crc;
    std::memcpy(&type, bytes.data() + offset, 4);
    std::memcpy(&length, bytes.data() + offset + 4, 4);
    if (length > kMaxRecordBytes || bytes.size() - offset - kRecordOverhead < length) {
      damaged(length > kMaxRecordBytes ? "a record of implausible length" : "a record cut short");
      break;
    }
    const char* data = bytes.data() + offset + 8;
    std::memcpy(&crc, data + length, 4);
    if (crc != Crc(type, length, data)) {
      damaged("a record failing its CRC");
      break;
    }
    payload.assign(data, length);
    try {
      Replay(type, payload, &read.snapshot);  // decodes all of a record before applying it
    } catch (const DecodeError& e) {
      damaged(std::string("an unreadable record (") + e.what() + ")");
      break;
    }
    offset += kRecordOverhead + length;
    ++read.records;
  }
  read.valid_bytes = static_cast<int64_t>(offset);
  return read;
}

SlamJournalWriter::SlamJournalWriter(const std::string& path, int64_t valid_bytes,
                                     double sync_period_s)
    : path_(path), sync_period_us_(std::llround(sync_period_s * 1e6)) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error("cannot open SLAM journal " + path + ": " + ErrnoText());
  const int64_t size = ::lseek(fd_, 0, SEEK_END);
  const bool fresh = size == 0 || valid_bytes <= 0;
  const int64_t keep = fresh ? 0 : std::min<int64_t>(valid_bytes, size);
  if (::ftruncate(fd_, keep) != 0 || ::lseek(fd_, keep, SEEK_SET) != keep) {
    const std::string why = ErrnoText();
    ::close(fd_);
    throw std::runtime_error("cannot cut SLAM journal " + path +
                             " to its last whole record: " + why);
  }
  if (fresh) pending_.assign(kMagic, sizeof(kMagic));
  Sync();
  if (error_) {
    ::close(fd_);
    throw std::runtime_error(*error_);
  }
}

SlamJournalWriter::~SlamJournalWriter() {
  Sync();
  ::close(fd_);
}

void SlamJournalWriter::Append(uint32_t type, const std::string& payload) {
  if (error_) return;
  const uint32_t length = static_cast<uint32_t>(payload.size());
  const uint32_t crc = Crc(type, length, payload.data());
  pending_.append(reinterpret_cast<const char*>(&type), 4);
  pending_.append(reinterpret_cast<const char*>(&length), 4);
  pending_.append(payload);
  pending_.append(reinterpret_cast<const char*>(&crc), 4);
}

void SlamJournalWriter::OnKeyframe(const KeyframeRecord& k,
                                   const std::optional<PoseGraphEdge>& sequential_edge) {
  Encoder e;
  e.Put<int32_t>(k.id);
  e.Put<int64_t>(k.utime);
  e.PutPose(k.odom_pose);
  e.PutPose(k.pose);
  e.Put<uint8_t>(k.in_map ? 1 : 0);
  const LidarScan& scan = k.scan;
  e.Put<int64_t>(scan.utime);
  e.Put<int64_t>(scan.seq);
  e.PutPose(scan.sensor_pose);
  e.Put(scan.angle_min_rad);
  e.Put(scan.angle_increment_rad);
  e.Put(scan.range_min_m);
  e.Put(scan.range_max_m);
  e.Put<uint32_t>(static_cast<uint32_t>(scan.range_m.size()));
  e.bytes().append(reinterpret_cast<const char*>(scan.range_m.data()),
                   scan.range_m.size() * sizeof(float));
  e.Put<uint8_t>(scan.beam_time_s.empty() ? 0 : 1);  // else one per beam (LidarScan)
  e.bytes().append(reinterpret_cast<const char*>(scan.beam_time_s.data()),
                   scan.beam_time_s.size() * sizeof(float));
  e.Put<uint8_t>(sequential_edge ? 1 : 0);
  if (sequential_edge) e.PutEdge(*sequential_edge);
  Append(kKeyframe, e.bytes());
}

void SlamJournalWriter::OnLoopClosureAdded(const PoseGraphEdge& edge) {
  Encoder e;
  e.PutEdge(edge);
  Append(kLoopClosureAdded, e.bytes());
}

void SlamJournalWriter::OnEdgeRemoved(const PoseGraphEdge& edge) {
  Encoder e;
  e.PutEdge(edge);
  Append(kEdgeRemoved, e.bytes());
}

void SlamJournalWriter::OnOptimized(const std::vector<PoseGraphNode>& nodes) {
  Encoder e;
  e.Put<uint32_t>(static_cast<uint32_t>(nodes.size()));
  for (const PoseGraphNode& node : nodes) e.PutPose(node.pose);
  pose_bytes_written_ += static_cast<int64_t>(e.bytes().size() + kRecordOverhead);
  Append(kOptimized, e.bytes());
}

void SlamJournalWriter::OnState(const SlamState& state) {
  Encoder e;
  PutCounters(&e, state.counters);
  e.Put<int32_t>(state.last_closure_attempt_node);
  e.Put<uint8_t>(state.last_mapped_odom_pose ? 1 : 0);
  if (state.last_mapped_odom_pose) e.PutPose(*state.last_mapped_odom_pose);
  e.PutPose(state.odometry_correction);
  Append(kState, e.bytes());
}

void SlamJournalWriter::Fail(const std::string& what) {
  if (!error_) error_ = "SLAM journal " + path_ + ": " + what + "; journaling stopped";
  pending_.clear();
}

void SlamJournalWriter::Commit(int64_t utime) {
  if (error_) return;
  if (!WriteAll(fd_, pending_)) {
    Fail("write failed: " + ErrnoText());
    return;
  }
  bytes_written_ += static_cast<int64_t>(pending_.size());
  pending_.clear();
  if (utime - last_sync_utime_ >= sync_period_us_ || utime < last_sync_utime_) {
    last_sync_utime_ = utime;
    if (::fdatasync(fd_) != 0) Fail("sync failed: " + ErrnoText());
  }
}

void SlamJournalWriter::Sync() {
  Commit(last_sync_utime_);
  if (!error_ && ::fdatasync(fd_) != 0) Fail("sync failed: " + ErrnoText());
}

bool SlamJournalWriter::WantsRewrite() const {
  constexpr int64_t kMinRewriteBytes = int64_t{1} << 20;
  return !error_ && bytes_written_ > kMinRewriteBytes && 2 * pose_bytes_written_ > bytes_written_;
}

bool SlamJournalWriter::Rewrite(const SlamSnapshot& snapshot, std::string* why_not) {
  Commit(last_sync_utime_);  // nothing of the old journal left pending
  if (error_) {
    *why_not = *error_;
    return false;
  }
  // The records of `snapshot`, built in pending_ by the same encoders as live records.
  pending_.assign(kMagic, sizeof(kMagic));
  std::size_t emitted = 0;  // keyframes written so far
  auto emit_keyframe = [&](const std::optional<PoseGraphEdge>& edge) {
    OnKeyframe(snapshot.keyframes[emitted], edge);
    ++emitted;
  };
  if (!snapshot.keyframes.empty()) emit_keyframe(std::nullopt);
  for (const PoseGraphEdge& edge : snapshot.graph.edges) {
    const bool sequential = edge.kind == EdgeKind::kOdometry &&
                            edge.to_id == static_cast<int>(emitted) &&
                            edge.from_id + 1 == edge.to_id;
    if (sequential) {
      emit_keyframe(edge);
      continue;
    }
    const std::size_t needed = static_cast<std::size_t>(std::max(edge.from_id, edge.to_id)) + 1;
    while (emitted < needed && emitted < snapshot.keyframes.size()) emit_keyframe(std::nullopt);
    OnLoopClosureAdded(edge);
  }
  while (emitted < snapshot.keyframes.size()) emit_keyframe(std::nullopt);
  OnState(snapshot.state);

  try {
    WriteFileAtomically(path_, pending_);
  } catch (const std::exception& e) {
    *why_not = e.what();
    pending_.clear();         // the old journal is untouched: appending goes on there
    pose_bytes_written_ = 0;  // try again after as many poses more
    return false;
  }
  const int fd = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd < 0) {  // the old file is gone: appending to it would lose everything after
    Fail("cannot open it again after its rewrite: " + ErrnoText());
    *why_not = *error_;
    return false;
  }
  ::close(fd_);
  fd_ = fd;
  bytes_written_ = static_cast<int64_t>(pending_.size());
  pose_bytes_written_ = 0;
  pending_.clear();
  ++rewrites_;
  return true;
}

}  // namespace aslam
