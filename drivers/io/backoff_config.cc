#include "drivers/io/backoff_config.h"

#include <vector>

namespace aslam {

void ReadReconnectBackoff(const ConfigReader& c, double* initial_s, double* max_s) {
  constexpr const char* kKey = "reconnect_backoff_s";
  if (!c.Has(kKey)) return;
  std::vector<double> backoff;
  c.Read(kKey, &backoff);
  if (backoff.size() != 2 || !(backoff[0] > 0) || backoff[1] < backoff[0] || backoff[1] > 3600) {
    c.Fail(kKey, "must be [INITIAL_S, MAX_S] with 0 < INITIAL_S <= MAX_S <= 3600");
  }
  *initial_s = backoff[0];
  *max_s = backoff[1];
}

}  // namespace aslam
