// libFuzzer: arbitrary bytes as slam.journal through ReadSlamJournal and, when records
// read back, Slam::Restore. Damage is reported (SlamJournalRead::damage) or refused with a
// std::exception; a crash, a leak or undefined behaviour is a finding.

#include <cstddef>
#include <cstdint>
#include <exception>

#include "slam/slam_journal.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace aslam;
  const std::string path = WriteFuzzInput(data, size, ".journal");
  try {
    SlamJournalRead read = ReadSlamJournal(path);
    Slam slam(SlamOptions{});
    slam.Restore(std::move(read.snapshot));
    (void)slam.RenderMap();
  } catch (const std::exception&) {
  }
  return 0;
}
