// aslam-hokuyo: a Hokuyo lidar (SCIP 2.0) publishing LIDAR_SCAN: a URG-04LX over
// USB serial (--port) or a UST-10LX/20LX over Ethernet (--host), reconnecting
// whenever the device goes away (drivers/hokuyo/hokuyo_lcm.h).

#include <gflags/gflags.h>

#include "common/flags.h"
#include "drivers/hokuyo/hokuyo_lcm.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "", "config file with a `hokuyo:` section (default: built-in defaults)");
DEFINE_string(port, "", "serial port of a URG-04LX, e.g. /dev/ttyACM0 or /dev/hokuyo");
DEFINE_int32(baud, 0, "serial bit rate (USB ignores it; default: the config's, else 115200)");
DEFINE_string(host, "", "address of a UST-10LX/20LX (factory default 192.168.0.10)");
DEFINE_int32(tcp_port, 0, "TCP port of a UST (default: the config's, else 10940)");
DEFINE_string(model, "", "urg04lx, ust10lx, ust20lx or auto (from the sensor's PP MODL)");
DEFINE_double(status_period, 10.0, "seconds between status lines; 0 = never");

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
                    "aslam-hokuyo (--port DEV [--baud N] | --host ADDR [--tcp_port N]) "
                    "[--model M] [--config FILE] [--lcm_url URL]");
  aslam::HokuyoProcessOptions options;
  options.lcm_url = FLAGS_lcm_url;
  options.config_file = FLAGS_config;
  options.port = FLAGS_port;
  options.baud = FLAGS_baud;
  options.host = FLAGS_host;
  options.tcp_port = FLAGS_tcp_port;
  options.model = FLAGS_model;
  options.status_period_s = FLAGS_status_period;
  return aslam::RunHokuyoProcess(options);
}
