#include "drivers/hid_recorder.h"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "host/io/atomic_file.h"
#include "host/io/user_file.h"

namespace ardcell {

namespace {

bool parse_hex_byte(const std::string& tok, uint8_t& out) {
  if (tok.empty() || tok.size() > 2) return false;
  unsigned v = 0;
  for (char c : tok) {
    v <<= 4;
    if (c >= '0' && c <= '9')
      v |= unsigned(c - '0');
    else if (c >= 'a' && c <= 'f')
      v |= unsigned(c - 'a' + 10);
    else if (c >= 'A' && c <= 'F')
      v |= unsigned(c - 'A' + 10);
    else
      return false;
  }
  out = uint8_t(v);
  return true;
}

bool parse_uint(const std::string& tok, int base, uint64_t max, uint64_t& out) {
  if (tok.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(tok.c_str(), &end, base);
  if (errno || *end || tok[0] == '-' || v > max) return false;
  out = v;
  return true;
}

// "<size> b0 b1 ..." with exactly size bytes.
bool parse_sized_bytes(std::istringstream& in, std::vector<uint8_t>& out, std::string& why) {
  std::string tok;
  uint64_t size = 0;
  if (!(in >> tok) || !parse_uint(tok, 10, 1 << 20, size)) {
    why = "expected a decimal byte count";
    return false;
  }
  out.clear();
  while (in >> tok) {
    uint8_t b = 0;
    if (!parse_hex_byte(tok, b)) {
      why = "\"" + tok + "\" is not a hex byte";
      return false;
    }
    out.push_back(b);
  }
  if (out.size() != size) {
    why = "says " + std::to_string(size) + " bytes but has " + std::to_string(out.size());
    return false;
  }
  return true;
}

}  // namespace

bool parse_hid_recording(const std::string& text, HidRecording& out, std::string& error) {
  HidRecording rec;
  bool have_descriptor = false;
  std::string pending_comment;
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  auto fail = [&](const std::string& why) {
    error = std::to_string(number) + ": " + why;  // read_hid_recording: "path:N: why"
    return false;
  };
  while (std::getline(lines, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line[0] == '#') {
      std::string c = line.substr(1);
      if (!c.empty() && c[0] == ' ') c.erase(0, 1);
      if (!pending_comment.empty()) pending_comment += '\n';
      pending_comment += c;
      continue;
    }
    if (line.size() < 2 || line[1] != ':') return fail("expected a line starting R:, N:, I:, E:");
    const char kind = line[0];
    std::string rest = line.substr(2);
    const auto first = rest.find_first_not_of(' ');
    rest = first == std::string::npos ? std::string() : rest.substr(first);
    std::istringstream in(rest);
    std::string why;
    switch (kind) {
      case 'R':
        if (have_descriptor) return fail("a second R: line (one device per file)");
        if (!parse_sized_bytes(in, rec.descriptor, why)) return fail("R: " + why);
        have_descriptor = true;
        pending_comment.clear();
        break;
      case 'N':
        rec.name = rest;
        pending_comment.clear();
        break;
      case 'P':
        rec.phys = rest;
        pending_comment.clear();
        break;
      case 'D':
        pending_comment.clear();
        break;
      case 'I': {
        std::string b, v, p;
        uint64_t bus = 0, vendor = 0, product = 0;
        if (!(in >> b >> v >> p) || !parse_uint(b, 16, 0xffff, bus) ||
            !parse_uint(v, 16, 0xffff, vendor) || !parse_uint(p, 16, 0xffff, product))
          return fail("I: expected three hex numbers: bus vendor product");
        rec.bus = uint32_t(bus);
        rec.vendor = uint32_t(vendor);
        rec.product = uint32_t(product);
        pending_comment.clear();
        break;
      }
      case 'E': {
        std::string ts;
        if (!(in >> ts)) return fail("E: expected a timestamp seconds.micros");
        char* end = nullptr;
        const double t = std::strtod(ts.c_str(), &end);
        if (*end || !(t >= 0) || t > 1e12) return fail("E: bad timestamp \"" + ts + "\"");
        HidEvent e;
        e.time = t;
        if (!parse_sized_bytes(in, e.data, why)) return fail("E: " + why);
        if (e.data.empty()) return fail("E: an event needs at least one byte");
        if (!rec.events.empty() && t < rec.events.back().time)
          return fail("E: timestamp goes backwards");
        e.comment = std::move(pending_comment);
        pending_comment.clear();
        rec.events.push_back(std::move(e));
        break;
      }
      default:
        return fail(std::string("unknown line kind \"") + kind + ":\"");
    }
  }
  if (!have_descriptor) {
    error = "no R: line (report descriptor)";
    return false;
  }
  out = std::move(rec);
  return true;
}

bool read_hid_recording(const std::string& path, HidRecording& out, std::string& error) {
  std::string text;
  if (Status s = read_user_file(path, kMaxRecordingBytes, "a hid-recorder file", text); !s) {
    error = s.message();
    return false;
  }
  std::string why;
  if (!parse_hid_recording(text, out, why)) {
    error = path + (why.empty() || !std::isdigit(static_cast<unsigned char>(why[0])) ? ": " : ":") +
            why;
    return false;
  }
  return true;
}

std::string format_hid_event(const HidEvent& e) {
  char buf[48];
  const long long secs = (long long)e.time;
  const long micros = long((e.time - double(secs)) * 1e6 + 0.5);
  std::snprintf(buf, sizeof buf, "E: %06lld.%06ld %zu", secs + micros / 1000000, micros % 1000000,
                e.data.size());
  std::string s = buf;
  for (uint8_t b : e.data) {
    std::snprintf(buf, sizeof buf, " %02x", b);
    s += buf;
  }
  return s;
}

std::string format_hid_recording(const HidRecording& rec) {
  std::string s = "R: " + std::to_string(rec.descriptor.size());
  char buf[64];
  for (uint8_t b : rec.descriptor) {
    std::snprintf(buf, sizeof buf, " %02x", b);
    s += buf;
  }
  s += "\nN: " + rec.name + "\n";
  if (!rec.phys.empty()) s += "P: " + rec.phys + "\n";
  std::snprintf(buf, sizeof buf, "I: %x %04x %04x\n", rec.bus, rec.vendor, rec.product);
  s += buf;
  for (const HidEvent& e : rec.events) {
    if (!e.comment.empty()) {
      std::istringstream c(e.comment);
      std::string l;
      while (std::getline(c, l)) s += "# " + l + "\n";
    }
    s += format_hid_event(e) + "\n";
  }
  return s;
}

bool write_hid_recording(const std::string& path, const HidRecording& rec, std::string& error) {
  // Durable: a recording ended by SIGTERM (systemctl stop, a shutdown) must survive the power
  // going off right after.
  AtomicFile file;
  Status s = file.open(path);
  if (s) {
    const std::string text = format_hid_recording(rec);
    file.write(text.data(), text.size());
    s = file.commit(true);
  }
  if (!s) error = s.message();
  return bool(s);
}

}  // namespace ardcell
