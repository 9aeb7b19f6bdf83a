#include "drivers/gpio_buttons.h"

#include <toml++/toml.h>
#include <fstream>
#include <sstream>

#include "host/io/user_file.h"

namespace ardcell {

namespace {
constexpr std::string_view kActions[] = {"next", "previous", "reset", "pause"};

std::string at(std::string_view source, const toml::source_region& r) {
  return std::string(source) + ":" + std::to_string(r.begin.line) + ": ";
}
}  // namespace

Status parse_gpio_config(std::string_view text, std::string_view source, GpioConfig& out) {
  out = GpioConfig{};
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    return Status::error(at(source, e.source()) + std::string(e.description()));
  }
  for (auto&& [key, node] : root) {
    const std::string k(key.str());
    if (k == "chip") {
      if (!node.is_string())
        return Status::error(at(source, node.source()) + "chip: expected a string (gpiochip0)");
      out.chip = *node.value<std::string>();
    } else if (k == "debounce_ms") {
      const auto v = node.value<int64_t>();
      if (!node.is_integer() || *v < 0 || *v > 1000)
        return Status::error(at(source, node.source()) +
                             "debounce_ms: expected an integer in [0, 1000]");
      out.debounce_ms = int(*v);
    } else if (k == "button") {
      const toml::array* arr = node.as_array();
      if (!arr)
        return Status::error(at(source, node.source()) + "button: expected [[button]] tables");
      for (const toml::node& b : *arr) {
        const toml::table* t = b.as_table();
        if (!t) return Status::error(at(source, b.source()) + "button: expected a table");
        GpioButton button;
        bool has_line = false, has_action = false;
        for (auto&& [bk, bv] : *t) {
          const std::string name(bk.str());
          if (name == "line") {
            const auto v = bv.value<int64_t>();
            if (!bv.is_integer() || *v < 0 || *v > 1023)
              return Status::error(at(source, bv.source()) +
                                   "button.line: expected a line offset in [0, 1023]");
            button.line = unsigned(*v);
            has_line = true;
          } else if (name == "action") {
            const auto v = bv.value<std::string>();
            bool found = false;
            for (size_t i = 0; v && i < std::size(kActions); ++i)
              if (*v == kActions[i]) {
                button.action = ButtonAction(i);
                found = true;
              }
            if (!found)
              return Status::error(
                  at(source, bv.source()) +
                  "button.action: expected one of next | previous | reset | pause");
            has_action = true;
          } else if (name == "active_low") {
            if (!bv.is_boolean())
              return Status::error(at(source, bv.source()) +
                                   "button.active_low: expected true or false");
            button.active_low = *bv.value<bool>();
          } else {
            return Status::error(at(source, bk.source()) + "button." + name +
                                 ": unknown key; expected one of: line, action, active_low");
          }
        }
        if (!has_line || !has_action)
          return Status::error(at(source, b.source()) + "button: expected both line and action");
        out.buttons.push_back(button);
      }
    } else {
      return Status::error(at(source, key.source()) + k +
                           ": unknown key; expected one of: chip, debounce_ms, button");
    }
  }
  if (out.buttons.empty())
    return Status::error(std::string(source) + ": no [[button]] tables (expected at least one)");
  return Status::ok();
}

Status load_gpio_config(const std::string& path, GpioConfig& out) {
  std::string text;
  if (Status s = read_user_file(path, kMaxTextConfigBytes, "a GPIO config TOML file", text); !s)
    return s;
  return parse_gpio_config(text, path, out);
}

void SimulatedGpioSource::push(const GpioEdge& e) {
  {
    std::lock_guard lock(mutex_);
    edges_.push_back(e);
  }
  cv_.notify_all();
}

void SimulatedGpioSource::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  cv_.notify_all();
}

int SimulatedGpioSource::wait(std::span<GpioEdge> out, int timeout_ms) {
  std::unique_lock lock(mutex_);
  cv_.wait_for(lock, std::chrono::milliseconds(timeout_ms),
               [&] { return !edges_.empty() || closed_; });
  if (edges_.empty()) return closed_ ? -1 : 0;
  int n = 0;
  while (!edges_.empty() && size_t(n) < out.size()) {
    out[size_t(n++)] = edges_.front();
    edges_.pop_front();
  }
  return n;
}

LiveCommand command_for(ButtonAction action) {
  switch (action) {
    case ButtonAction::kNextPreset:
      return LiveCommand::make(LiveCommandKind::kNextPreset);
    case ButtonAction::kPrevPreset:
      return LiveCommand::make(LiveCommandKind::kPrevPreset);
    case ButtonAction::kReset:
      return LiveCommand::make(LiveCommandKind::kReset);
    case ButtonAction::kPause:
      return LiveCommand::make(LiveCommandKind::kTogglePause);
  }
  return LiveCommand::make(LiveCommandKind::kInputActivity);
}

ButtonHandler::ButtonHandler(const GpioConfig& config, CommandQueue& commands)
    : debounce_ns_(int64_t(config.debounce_ms) * 1'000'000), commands_(commands) {
  for (const GpioButton& b : config.buttons) lines_.push_back({b.line, b.action, b.active_low});
}

bool ButtonHandler::on_edge(const GpioEdge& edge) {
  for (LineState& s : lines_) {
    if (s.line != edge.line) continue;
    if (edge.time_ns - s.last_ns < debounce_ns_) {
      ++bounces_;
      return false;
    }
    const bool active = edge.rising != s.active_low;  // rising on active-high, falling on low
    if (active == s.pressed) return false;            // no change of level: nothing to do
    s.last_ns = edge.time_ns;
    s.pressed = active;
    if (!active) return false;
    ++presses_;
    commands_.push(command_for(s.action));
    commands_.push(LiveCommand::make(LiveCommandKind::kInputActivity));
    return true;
  }
  return false;
}

GpioButtons::GpioButtons(std::unique_ptr<GpioEventSource> source, const GpioConfig& config,
                         CommandQueue& commands)
    : source_(std::move(source)), handler_(config, commands) {
  thread_ = std::thread([this] {
    GpioEdge edges[16];
    while (!stop_.load()) {
      const int n = source_->wait(edges, 100);
      if (n < 0) break;
      for (int i = 0; i < n; ++i) handler_.on_edge(edges[i]);
    }
  });
}

GpioButtons::~GpioButtons() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

}  // namespace ardcell
