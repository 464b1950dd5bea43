#pragma once

// aslam-viewer as a whole: live on a bus, or a finished run's log with a time slider; serves
// the page and pushes updates at its rate until stopped.

#include <atomic>
#include <string>

namespace aslam {

struct ViewerOptions {
  std::string lcm_url;   // live: the bus ("" = $LCM_DEFAULT_URL, else udpm with ttl=0)
  std::string log_path;  // replay this lcm log instead (no control then)
  std::string bind_address = "127.0.0.1";
  int port = 8080;
  double rate_hz = 2.0;           // updates per second to each page
  double status_period_s = 10.0;  // a status line on stdout this often; 0 = none

  // Throws std::invalid_argument naming the flag and value.
  void Validate() const;
};

// Runs until `stop` turns true; returns the process exit code (1, with a line on stderr,
// when the bus, the log or the port cannot be opened).
int RunViewer(const ViewerOptions& options, const std::atomic<bool>& stop);

}  // namespace aslam
