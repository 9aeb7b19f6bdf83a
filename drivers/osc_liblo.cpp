#include "drivers/osc_liblo.h"

#include <arpa/inet.h>
#include <lo/lo.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <vector>

#include "host/scenes/preset.h"

namespace ardcell {

namespace {
double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// A numeric argument of any OSC numeric type (or T/F). liblo's arguments are only 4-byte
// aligned, so they are copied out rather than read through the lo_arg union.
bool numeric_arg(char type, const lo_arg* a, double& out) {
  const void* p = a;
  switch (type) {
    case LO_FLOAT: {
      float f;
      std::memcpy(&f, p, sizeof f);
      out = f;
      return true;
    }
    case LO_DOUBLE:
      std::memcpy(&out, p, sizeof out);
      return true;
    case LO_INT32: {
      int32_t i;
      std::memcpy(&i, p, sizeof i);
      out = i;
      return true;
    }
    case LO_INT64: {
      int64_t h;
      std::memcpy(&h, p, sizeof h);
      out = double(h);
      return true;
    }
    case LO_TRUE:
      out = 1;
      return true;
    case LO_FALSE:
      out = 0;
      return true;
    default:
      return false;
  }
}
bool is_string(char type) { return type == LO_STRING || type == LO_SYMBOL; }
}  // namespace

std::unique_ptr<OscServer> OscServer::start(int port, const std::string& bind_address,
                                            CommandQueue& commands, StrokeRing& strokes,
                                            Status& error) {
  std::unique_ptr<OscServer> s(new OscServer(commands, strokes));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(uint16_t(port));
  if (port < 0 || port > 65535 || inet_pton(AF_INET, bind_address.c_str(), &addr.sin_addr) != 1) {
    error = Status::error("osc: " + bind_address + ":" + std::to_string(port) +
                          ": expected an IPv4 address and a port in [0, 65535]");
    return nullptr;
  }
  s->fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (s->fd_ < 0 || bind(s->fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    error = Status::error("osc: cannot bind UDP " + bind_address + ":" + std::to_string(port) +
                          " (" + std::strerror(errno) + "); expected a free port");
    return nullptr;
  }
  socklen_t len = sizeof addr;
  getsockname(s->fd_, reinterpret_cast<sockaddr*>(&addr), &len);
  s->port_ = ntohs(addr.sin_port);
  s->start_time_ = seconds_now();
  OscServer* raw = s.get();
  s->thread_ = std::thread([raw] {
    std::vector<char> buf(65536);
    while (!raw->stop_.load()) {
      pollfd p{raw->fd_, POLLIN, 0};
      if (poll(&p, 1, 100) <= 0) continue;
      const ssize_t n = recv(raw->fd_, buf.data(), buf.size(), 0);
      if (n > 0) raw->dispatch(buf.data(), size_t(n));
    }
  });
  error = Status::ok();
  return s;
}

OscServer::~OscServer() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
  if (fd_ >= 0) close(fd_);
}

std::string OscServer::last_error() const {
  std::lock_guard lock(error_mutex_);
  return last_error_;
}

bool OscServer::reject(const std::string& why) {
  ++rejected_;
  std::fprintf(stderr, "osc: %s\n", why.c_str());
  std::lock_guard lock(error_mutex_);
  last_error_ = why;
  return false;
}

bool OscServer::dispatch(const void* data, size_t size) {
  std::vector<char> copy(static_cast<const char*>(data), static_cast<const char*>(data) + size);
  if (size >= 8 && std::memcmp(copy.data(), "#bundle", 8) == 0)
    return reject("bundles are not supported; expected plain OSC messages");
  int result = 0;
  lo_message m = lo_message_deserialise(copy.data(), size, &result);
  if (!m) return reject("malformed OSC message (liblo error " + std::to_string(result) + ")");
  const std::string path = lo_get_path(copy.data(), ssize_t(size));
  const char* types_c = lo_message_get_types(m);
  const std::string types = types_c ? types_c : "";
  lo_arg** argv = lo_message_get_argv(m);
  const int argc = lo_message_get_argc(m);
  struct Free {
    lo_message m;
    ~Free() { lo_message_free(m); }
  } free_message{m};

  auto push = [&](const LiveCommand& c) {
    if (!commands_.push(c)) return reject(path + ": command queue full");
    commands_.push(LiveCommand::make(LiveCommandKind::kInputActivity));
    ++handled_;
    return true;
  };
  auto text_arg = [&](int i) -> std::string {
    return i < argc && is_string(types[size_t(i)])
               ? std::string(reinterpret_cast<const char*>(argv[i]))
               : std::string();
  };
  auto usage = [&](const char* expected) {
    return reject(path + " ," + types + ": expected " + expected);
  };

  if (path == "/ardcell/preset") {
    if (argc != 1 || !is_string(types[0])) return usage("s NAME");
    return push(LiveCommand::with_text(LiveCommandKind::kSelectPreset, text_arg(0)));
  }
  if (path == "/ardcell/preset/next") return push(LiveCommand::make(LiveCommandKind::kNextPreset));
  if (path == "/ardcell/preset/prev") return push(LiveCommand::make(LiveCommandKind::kPrevPreset));
  if (path == "/ardcell/param") {
    if (argc != 2 || !is_string(types[0])) return usage("s KEY and a value");
    const std::string key = text_arg(0);
    const ParamSpec* spec = find_param(key);
    if (!spec) return reject(path + ": unknown key '" + key + "' (see `ardcell live --keys`)");
    double value = 0;
    if (is_string(types[1]) && spec->kind == ParamKind::kChoice) {
      const std::string name = text_arg(1);
      value = -1;
      for (size_t i = 0; i < spec->choices.size(); ++i)
        if (spec->choices[i] == name) value = double(i);
      if (value < 0) return reject(path + ": " + key + ": expected " + param_expectation(*spec));
    } else if (!numeric_arg(types[1], argv[1], value)) {
      return reject(path + ": " + key + ": expected " + param_expectation(*spec));
    }
    std::string why;
    Preset probe;
    if (spec->structural || !set_param(probe, *spec, value, &why))
      return reject(
          path + ": " +
          (spec->structural ? key + ": changes the grid or models; switch presets" : why));
    return push(
        LiveCommand::make(LiveCommandKind::kSetParam, value, int(spec - preset_params().data())));
  }
  if (path == "/ardcell/mode") {
    const ParamSpec* mode = find_param("input.mode");
    double index = -1;
    if (argc == 1 && is_string(types[0])) {
      const std::string name = text_arg(0);
      for (size_t i = 0; i < mode->choices.size(); ++i)
        if (mode->choices[i] == name) index = double(i);
    } else if (argc == 1) {
      (void)numeric_arg(types[0], argv[0], index);
    }
    if (index < 0 || index > mode->max) return usage(param_expectation(*mode).c_str());
    return push(LiveCommand::make(LiveCommandKind::kSetMode, index));
  }
  if (path == "/ardcell/stroke" || path == "/ardcell/stroke/end") {
    StrokeSample s;
    s.time = seconds_now() - start_time_;
    if (path == "/ardcell/stroke") {
      double x = 0, y = 0, p = 1;
      if (argc < 2 || argc > 3 || !numeric_arg(types[0], argv[0], x) ||
          !numeric_arg(types[1], argv[1], y) || (argc == 3 && !numeric_arg(types[2], argv[2], p)))
        return usage("f X f Y [f PRESSURE]");
      s.x = float(x);
      s.y = float(y);
      s.pressure = float(p < 0 ? 0 : (p > 1 ? 1 : p));
      s.buttons = s.pressure > 0 ? uint32_t(kButtonTip) : 0u;
      s.in_range = true;
    }
    if (!strokes_.push(s)) return reject(path + ": stroke ring full");
    ++handled_;
    return true;
  }
  if (path == "/ardcell/record/start")
    return push(LiveCommand::with_text(LiveCommandKind::kRecordStart, text_arg(0)));
  if (path == "/ardcell/record/stop") return push(LiveCommand::make(LiveCommandKind::kRecordStop));
  if (path == "/ardcell/screenshot")
    return push(LiveCommand::with_text(LiveCommandKind::kScreenshot, text_arg(0)));
  if (path == "/ardcell/reset") return push(LiveCommand::make(LiveCommandKind::kReset));
  if (path == "/ardcell/hud") return push(LiveCommand::make(LiveCommandKind::kToggleHud));
  if (path == "/ardcell/pause") {
    double v = 0;
    if (argc == 0) return push(LiveCommand::make(LiveCommandKind::kTogglePause));
    if (argc == 1 && numeric_arg(types[0], argv[0], v))
      return push(LiveCommand::make(LiveCommandKind::kSetPause, v != 0 ? 1 : 0));
    return usage("no argument (toggle) or i 0|1");
  }
  return reject(path +
                ": unknown address (expected /ardcell/preset, /ardcell/param, "
                "/ardcell/mode, /ardcell/stroke, /ardcell/record/start, ...)");
}

}  // namespace ardcell
