#pragma once
// Pen tablets through hidapi (hidraw back end): enumerate pen digitizers (HID usage page
// 0x0D), read each device's report descriptor (hid_get_report_descriptor on hidapi >= 0.14,
// sysfs /sys/class/hidraw/hidrawN/device/report_descriptor before), decode its pen generically
// (drivers/hid_descriptor.h) and feed stroke samples into a lock-free ring from a reader
// thread. Hot-plug: an unplugged tablet prints one line and the program keeps running; when
// it comes back, reading resumes. Without permission: one line naming the udev rule.
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "drivers/hid_recorder.h"
#include "host/paint/stroke.h"

namespace ardcell {

inline constexpr const char* kTabletUdevRule = "drivers/udev/70-ardcell-tablet.rules";

struct TabletInfo {
  std::string path;  // /dev/hidrawN
  std::string name;  // manufacturer + product
  uint16_t vendor = 0, product = 0;
  int interface_number = -1;
  uint16_t usage_page = 0, usage = 0;
  bool readable = false;  // this user may open it
};

// Every HID interface whose top-level usage page is 0x0D (Digitizer).
std::vector<TabletInfo> list_tablets();

// The raw report descriptor of a hidraw device, or false with `error`.
bool read_report_descriptor(const std::string& path, std::vector<uint8_t>& out, std::string& error);

// One line for a device that cannot be opened for lack of permission.
std::string tablet_permission_hint(const std::string& path);

// A live tablet as a StrokeSource: a reader thread per device (the first pen digitizer
// found, re-found after unplugging), samples through a ring. Messages (plugged, unplugged,
// no permission, no tablet) go to `log` as single lines.
class HidTabletSource : public StrokeSource {
 public:
  explicit HidTabletSource(std::FILE* log = stderr);
  ~HidTabletSource() override;
  std::size_t poll(double now, std::span<StrokeSample> out) override;
  std::string describe() const override;

 private:
  void run();
  RingStrokeSource ring_;
  std::FILE* log_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// Records raw input reports of one tablet (the first pen digitizer, or `path`) in
// hid-recorder format until `stop` is set or `max_seconds` pass; written atomically.
bool record_tablet(const std::string& path, const std::string& out_file,
                   const std::atomic<bool>& stop, double max_seconds, std::FILE* log,
                   std::string& error);

}  // namespace ardcell
