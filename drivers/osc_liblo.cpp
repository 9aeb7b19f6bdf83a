#include "drivers/osc_liblo.h"

#include <arpa/inet.h>
#include <lo/lo.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdlib>
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

// The sender's text as logged: at most kMaxEchoedChars, non-printable bytes as \xNN.
std::string echoed(std::string_view text) {
  return escaped_prefix(text, RemoteLog::kMaxEchoedChars);
}

// A preset as a sender may name it: letters, digits, '.', '-', '_'; no path, no "..".
bool plain_name(const std::string& name) {
  if (name.empty() || name.size() > 128 || name.find("..") != std::string::npos) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_')
      return false;
  return true;
}

std::string real_path(const std::string& path) {
  char* r = ::realpath(path.c_str(), nullptr);
  if (!r) return "";
  std::string out = r;
  std::free(r);
  return out;
}
}  // namespace

std::string OscServer::resolve_preset(const std::string& name, std::string& why) const {
  if (!plain_name(name)) {
    why = "expected a preset name or a .toml file name in a preset folder (no paths)";
    return "";
  }
  const bool toml = name.ends_with(".toml");
  if (!toml)
    for (const std::string& n : preset_names())
      if (n == name) return name;
  for (const std::string& folder : preset_folders_) {
    const std::string root = real_path(folder);
    if (root.empty()) continue;
    // realpath follows every symlink: what it names must still lie inside the folder.
    const std::string file = real_path(folder + "/" + (toml ? name : name + ".toml"));
    struct stat st {};
    if (file.empty() || !file.starts_with(root + "/") || ::stat(file.c_str(), &st) != 0 ||
        !S_ISREG(st.st_mode))
      continue;
    if (file.size() >= LiveCommand{}.text.size()) continue;
    return file;
  }
  why = preset_folders_.empty()
            ? "not a built-in preset (no --preset-dir is given, so only built-in names)"
            : "not a built-in preset nor a preset file in the preset folders";
  return "";
}

std::unique_ptr<OscServer> OscServer::start(int port, const std::string& bind_address,
                                            CommandQueue& commands, StrokeRing& strokes,
                                            RemoteLog& log, Status& error,
                                            std::vector<std::string> preset_folders) {
  std::unique_ptr<OscServer> s(new OscServer(commands, strokes, log));
  s->preset_folders_ = std::move(preset_folders);
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
  log_.line("osc", why);
  {
    std::lock_guard lock(error_mutex_);
    last_error_ = why;
  }
  ++rejected_;  // last: whoever sees the count sees this reason
  return false;
}

bool OscServer::dispatch(const void* data, size_t size) {
  std::vector<char> copy(static_cast<const char*>(data), static_cast<const char*>(data) + size);
  if (size >= 8 && std::memcmp(copy.data(), "#bundle", 8) == 0)
    return reject("bundles are not supported; expected plain OSC messages");
  int result = 0;
  lo_message m = lo_message_deserialise(copy.data(), size, &result);
  if (!m) return reject("malformed OSC message (liblo error " + std::to_string(result) + ")");
  const std::string address = lo_get_path(copy.data(), ssize_t(size));
  const char* types_c = lo_message_get_types(m);
  const std::string types_raw = types_c ? types_c : "";
  // Only escaped prefixes of the sender's text reach the log (`path` and `types` below).
  const std::string path = echoed(address), types = echoed(types_raw);
  lo_arg** argv = lo_message_get_argv(m);
  const int argc = lo_message_get_argc(m);
  struct Free {
    lo_message m;
    ~Free() { lo_message_free(m); }
  } free_message{m};

  auto push = [&](LiveCommand c) {
    c.remote = true;  // what the loop logs about it goes through log_ too
    if (!commands_.push(c)) return reject(path + ": command queue full");
    commands_.push(LiveCommand::make(LiveCommandKind::kInputActivity));
    ++handled_;
    return true;
  };
  auto text_arg = [&](int i) -> std::string {
    return i < argc && is_string(types_raw[size_t(i)])
               ? std::string(reinterpret_cast<const char*>(argv[i]))
               : std::string();
  };
  auto usage = [&](const char* expected) {
    return reject(path + " ," + types + ": expected " + expected);
  };

  if (address == "/ardcell/preset") {
    if (argc != 1 || !is_string(types_raw[0])) return usage("s NAME");
    std::string why;
    const std::string preset = resolve_preset(text_arg(0), why);
    if (preset.empty()) return reject(path + ": " + echoed(text_arg(0)) + ": " + why);
    return push(LiveCommand::with_text(LiveCommandKind::kSelectPreset, preset));
  }
  if (address == "/ardcell/preset/next")
    return push(LiveCommand::make(LiveCommandKind::kNextPreset));
  if (address == "/ardcell/preset/prev")
    return push(LiveCommand::make(LiveCommandKind::kPrevPreset));
  if (address == "/ardcell/param") {
    if (argc != 2 || !is_string(types_raw[0])) return usage("s KEY and a value");
    const std::string key = text_arg(0);
    const ParamSpec* spec = find_param(key);
    if (!spec)
      return reject(path + ": unknown key '" + echoed(key) + "' (see `ardcell live --keys`)");
    double value = 0;
    if (is_string(types_raw[1]) && spec->kind == ParamKind::kChoice) {
      const std::string name = text_arg(1);
      value = -1;
      for (size_t i = 0; i < spec->choices.size(); ++i)
        if (spec->choices[i] == name) value = double(i);
      if (value < 0) return reject(path + ": " + key + ": expected " + param_expectation(*spec));
    } else if (!numeric_arg(types_raw[1], argv[1], value)) {
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
  if (address == "/ardcell/mode") {
    const ParamSpec* mode = find_param("input.mode");
    double index = -1;
    if (argc == 1 && is_string(types_raw[0])) {
      const std::string name = text_arg(0);
      for (size_t i = 0; i < mode->choices.size(); ++i)
        if (mode->choices[i] == name) index = double(i);
    } else if (argc == 1) {
      (void)numeric_arg(types_raw[0], argv[0], index);
    }
    if (index < 0 || index > mode->max) return usage(param_expectation(*mode).c_str());
    return push(LiveCommand::make(LiveCommandKind::kSetMode, index));
  }
  if (address == "/ardcell/stroke" || address == "/ardcell/stroke/end") {
    StrokeSample s;
    s.time = seconds_now() - start_time_;
    if (address == "/ardcell/stroke") {
      double x = 0, y = 0, p = 1;
      if (argc < 2 || argc > 3 || !numeric_arg(types_raw[0], argv[0], x) ||
          !numeric_arg(types_raw[1], argv[1], y) ||
          (argc == 3 && !numeric_arg(types_raw[2], argv[2], p)))
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
  // The sender names no files: generated names in the output folder (--screenshot-dir).
  if (address == "/ardcell/record/start") {
    if (argc != 0)
      return usage("no argument (recordings get generated names in the output folder)");
    return push(LiveCommand::make(LiveCommandKind::kRecordStart));
  }
  if (address == "/ardcell/record/stop")
    return push(LiveCommand::make(LiveCommandKind::kRecordStop));
  if (address == "/ardcell/screenshot") {
    if (argc != 0)
      return usage("no argument (screenshots get generated names in the output folder)");
    return push(LiveCommand::make(LiveCommandKind::kScreenshot));
  }
  if (address == "/ardcell/reset") return push(LiveCommand::make(LiveCommandKind::kReset));
  if (address == "/ardcell/hud") return push(LiveCommand::make(LiveCommandKind::kToggleHud));
  if (address == "/ardcell/pause") {
    double v = 0;
    if (argc == 0) return push(LiveCommand::make(LiveCommandKind::kTogglePause));
    if (argc == 1 && numeric_arg(types_raw[0], argv[0], v))
      return push(LiveCommand::make(LiveCommandKind::kSetPause, v != 0 ? 1 : 0));
    return usage("no argument (toggle) or i 0|1");
  }
  return reject(path +
                ": unknown address (expected /ardcell/preset, /ardcell/param, "
                "/ardcell/mode, /ardcell/stroke, /ardcell/record/start, ...)");
}

}  // namespace ardcell
