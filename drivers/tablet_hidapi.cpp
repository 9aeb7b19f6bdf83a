#include "drivers/tablet_hidapi.h"

#include <hidapi/hidapi.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <iterator>

#include "drivers/hid_descriptor.h"
#include "drivers/hid_report.h"

namespace ardcell {

namespace {

std::string narrow(const wchar_t* w) {
  std::string s;
  if (!w) return s;
  for (; *w; ++w) s += (*w < 128) ? char(*w) : '?';
  return s;
}

bool hidapi_ready() {
  static const bool ok = hid_init() == 0;
  return ok;
}

double now_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

}  // namespace

std::vector<TabletInfo> list_tablets() {
  std::vector<TabletInfo> out;
  if (!hidapi_ready()) return out;
  hid_device_info* all = hid_enumerate(0, 0);
  for (hid_device_info* d = all; d; d = d->next) {
    if (d->usage_page != 0x0D) continue;
    TabletInfo t;
    t.path = d->path ? d->path : "";
    t.name = narrow(d->manufacturer_string);
    const std::string product = narrow(d->product_string);
    if (!product.empty()) t.name += (t.name.empty() ? "" : " ") + product;
    t.vendor = d->vendor_id;
    t.product = d->product_id;
    t.interface_number = d->interface_number;
    t.usage_page = d->usage_page;
    t.usage = d->usage;
    t.readable = ::access(t.path.c_str(), R_OK) == 0;
    out.push_back(std::move(t));
  }
  hid_free_enumeration(all);
  return out;
}

bool read_report_descriptor(const std::string& path, std::vector<uint8_t>& out,
                            std::string& error) {
#if defined(HID_API_VERSION) && HID_API_VERSION >= HID_API_MAKE_VERSION(0, 14, 0)
  if (hidapi_ready()) {
    if (hid_device* dev = hid_open_path(path.c_str())) {
      unsigned char buf[HID_API_MAX_REPORT_DESCRIPTOR_SIZE];
      const int n = hid_get_report_descriptor(dev, buf, sizeof buf);
      hid_close(dev);
      if (n > 0) {
        out.assign(buf, buf + n);
        return true;
      }
    }
  }
#endif
  // hidraw: /dev/hidrawN -> /sys/class/hidraw/hidrawN/device/report_descriptor.
  const auto slash = path.rfind('/');
  const std::string node = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::string sys = "/sys/class/hidraw/" + node + "/device/report_descriptor";
  std::ifstream f(sys, std::ios::binary);
  if (!f) {
    error = sys + ": cannot read the report descriptor (" + std::strerror(errno) + ")";
    return false;
  }
  out.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  if (out.empty()) {
    error = sys + ": empty report descriptor";
    return false;
  }
  return true;
}

std::string tablet_permission_hint(const std::string& path) {
  return "tablet: no permission to read " + path + "; install the udev rule " + kTabletUdevRule +
         " (sudo cp " + kTabletUdevRule +
         " /etc/udev/rules.d/ && sudo udevadm control --reload-rules && sudo udevadm trigger),"
         " then replug the tablet";
}

HidTabletSource::HidTabletSource(std::FILE* log) : ring_("tablet", 4096), log_(log) {
  thread_ = std::thread([this] { run(); });
}

HidTabletSource::~HidTabletSource() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

std::size_t HidTabletSource::poll(double now, std::span<StrokeSample> out) {
  return ring_.poll(now, out);
}

std::string HidTabletSource::describe() const { return "tablet (hidapi)"; }

void HidTabletSource::run() {
  enum class Said { nothing, no_tablet, no_permission, unplugged };
  Said said = Said::nothing;
  auto say = [&](Said what, const std::string& line) {
    if (said == what) return;  // one line per situation, not one per retry
    said = what;
    if (log_) {
      std::fprintf(log_, "%s\n", line.c_str());
      std::fflush(log_);
    }
  };
  if (!hidapi_ready()) {
    say(Said::no_tablet, "tablet: hidapi could not start; running without a tablet");
    return;
  }
  const double t0 = now_seconds();
  std::vector<uint8_t> descriptor_bytes;
  while (!stop_.load()) {
    // Find a readable pen digitizer with a pen in its descriptor.
    const std::vector<TabletInfo> tablets = list_tablets();
    const TabletInfo* chosen = nullptr;
    HidDescriptor desc;
    std::vector<HidPenLayout> pens;
    for (const TabletInfo& t : tablets) {
      if (!t.readable) continue;
      std::string error;
      if (!read_report_descriptor(t.path, descriptor_bytes, error)) continue;
      if (!parse_hid_descriptor(descriptor_bytes, desc, error)) continue;
      pens = find_pens(desc);
      if (!pens.empty()) {
        chosen = &t;
        break;
      }
    }
    if (!chosen) {
      if (!tablets.empty() && !tablets.front().readable)
        say(Said::no_permission, tablet_permission_hint(tablets.front().path));
      else if (said != Said::unplugged)
        say(Said::no_tablet, "tablet: no pen tablet found; running without one");
      for (int i = 0; i < 10 && !stop_.load(); ++i) ::usleep(100000);
      continue;
    }
    hid_device* dev = hid_open_path(chosen->path.c_str());
    if (!dev) {
      say(Said::no_permission, tablet_permission_hint(chosen->path));
      ::usleep(1000000);
      continue;
    }
    if (log_) {
      std::fprintf(log_, "tablet: %s (%04x:%04x) on %s\n", chosen->name.c_str(), chosen->vendor,
                   chosen->product, chosen->path.c_str());
      std::fflush(log_);
    }
    said = Said::nothing;
    unsigned char buf[256];
    std::string error;
    while (!stop_.load()) {
      const int n = hid_read_timeout(dev, buf, sizeof buf, 100);
      if (n < 0) {
        say(Said::unplugged, "tablet: " + chosen->name + " unplugged; waiting for it to return");
        break;
      }
      if (n == 0) continue;
      const std::span<const uint8_t> raw(buf, std::size_t(n));
      for (const HidPenLayout& pen : pens) {
        HidPenState st;
        if (!decode_pen(pen, desc.uses_report_ids, raw, st, error)) continue;
        ring_.ring().push(pen_state_to_sample(pen, st, now_seconds() - t0));
      }
    }
    hid_close(dev);
  }
}

bool record_tablet(const std::string& path, const std::string& out_file,
                   const std::atomic<bool>& stop, double max_seconds, std::FILE* log,
                   std::string& error) {
  if (!hidapi_ready()) {
    error = "hidapi could not start";
    return false;
  }
  TabletInfo info;
  if (path.empty()) {
    const std::vector<TabletInfo> tablets = list_tablets();
    if (tablets.empty()) {
      error = "no pen tablet found (ardcell tablet list shows what is connected)";
      return false;
    }
    info = tablets.front();
  } else {
    info.path = path;
  }
  if (::access(info.path.c_str(), R_OK) != 0) {
    error = tablet_permission_hint(info.path);
    return false;
  }
  HidRecording rec;
  if (!read_report_descriptor(info.path, rec.descriptor, error)) return false;
  rec.name = info.name;
  rec.bus = 3;
  rec.vendor = info.vendor;
  rec.product = info.product;
  hid_device* dev = hid_open_path(info.path.c_str());
  if (!dev) {
    error = info.path + ": cannot open (" + narrow(hid_error(nullptr)) + ")";
    return false;
  }
  if (log)
    std::fprintf(log, "recording %s from %s; Ctrl-C stops\n", info.name.c_str(), info.path.c_str());
  const double t0 = now_seconds();
  unsigned char buf[256];
  while (!stop.load() && now_seconds() - t0 < max_seconds) {
    const int n = hid_read_timeout(dev, buf, sizeof buf, 100);
    if (n < 0) {
      if (log) std::fprintf(log, "tablet unplugged; keeping what was recorded\n");
      break;
    }
    if (n == 0) continue;
    HidEvent e;
    e.time = now_seconds() - t0;
    e.data.assign(buf, buf + n);
    rec.events.push_back(std::move(e));
  }
  hid_close(dev);
  return write_hid_recording(out_file, rec, error);
}

}  // namespace ardcell
