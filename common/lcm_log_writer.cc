#include "common/lcm_log_writer.h"

namespace aslam {

LcmLogWriter::LcmLogWriter(const std::string& path) : path_(path), log_(path, "w") {
  if (!log_.good()) throw std::runtime_error(path + ": cannot write an LCM log there");
}

void LcmLogWriter::WriteBytes(const std::string& channel, int64_t timestamp_us, const void* data,
                              int32_t size) {
  lcm::LogEvent event{};
  event.eventnum = events_;
  event.timestamp = timestamp_us;
  event.channel = channel;
  event.datalen = size;
  event.data = const_cast<void*>(data);  // LogFile only reads it
  if (log_.writeEvent(&event) != 0)
    throw std::runtime_error(path_ + ": writing the LCM log failed");
  ++events_;
}

}  // namespace aslam
