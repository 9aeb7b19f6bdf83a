#pragma once
// Stroke samples and where they come from. Every input device (pen tablet, mouse/touch, OSC,
// replay files) produces StrokeSamples through one StrokeSource interface; the painter
// (host/paint/paint.h) consumes them. Producer threads hand samples over through StrokeRing, a
// fixed-capacity lock-free single-producer/single-consumer ring (no allocation per sample).
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ardcell {

// Pen buttons, as bits of StrokeSample::buttons.
enum StrokeButton : uint32_t {
  kButtonTip = 1u << 0,        // tip switch (pen touches the surface)
  kButtonBarrel = 1u << 1,     // first barrel (side) switch
  kButtonSecondary = 1u << 2,  // secondary barrel / secondary tip switch
  kButtonThird = 1u << 3,      // any further button
};

// One sample of a pen (or mouse/touch pointer).
// Coordinates are normalized to the drawing area: x in [0, 1] from left to right, y in [0, 1]
// from top to bottom (tablet and screen convention); the painter maps them onto grid cells as
// (x * nx, y * ny). Values outside [0, 1] are allowed (off the canvas) and simply paint nothing.
struct StrokeSample {
  double time = 0;        // seconds, monotonic within one source
  float x = 0, y = 0;     // normalized position (see above)
  float pressure = 0;     // 0..1 (mouse: 1 while a button is held)
  float tilt_x = 0;       // degrees, positive = tip towards +x (0 when the device has no tilt)
  float tilt_y = 0;       // degrees, positive = tip towards +y
  uint32_t buttons = 0;   // StrokeButton bits; kButtonTip = touching
  bool in_range = false;  // the pen is near enough to be tracked (hover or touch)
  bool eraser = false;    // the eraser end (HID Invert/Eraser) is the one in range

  bool touching() const { return (buttons & kButtonTip) != 0; }
  friend bool operator==(const StrokeSample&, const StrokeSample&) = default;
};

// A source of stroke samples, polled once per frame by the consumer (the real-time loop).
class StrokeSource {
 public:
  virtual ~StrokeSource() = default;
  // Moves the samples that are due at `now` (seconds on the consumer's clock, counted from the
  // first poll; live sources ignore it) into out, oldest first. Returns how many were written
  // (<= out.size(); the rest stay for the next call). Never blocks, never allocates.
  virtual std::size_t poll(double now, std::span<StrokeSample> out) = 0;
  // True when the source will never produce another sample (a replay that has ended).
  virtual bool finished() const { return false; }
  // One line for logs: "tablet HUION Huion Tablet_GS1333", "replay spiral.jsonl", ...
  virtual std::string describe() const = 0;
};

// Lock-free single-producer/single-consumer ring of samples with a fixed power-of-two
// capacity, allocated once. push() from one thread, pop() from one other thread.
class StrokeRing {
 public:
  explicit StrokeRing(std::size_t capacity = 1024);
  StrokeRing(const StrokeRing&) = delete;
  StrokeRing& operator=(const StrokeRing&) = delete;

  // False (and the sample dropped) when the ring is full; dropped() counts those.
  bool push(const StrokeSample& s);
  bool pop(StrokeSample& s);
  // Pops up to out.size() samples; returns how many.
  std::size_t pop_many(std::span<StrokeSample> out);
  std::size_t capacity() const { return mask_ + 1; }
  std::size_t size() const;
  uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  std::unique_ptr<StrokeSample[]> slots_;
  std::size_t mask_;
  alignas(64) std::atomic<std::size_t> head_{0};  // next slot to write (producer)
  alignas(64) std::atomic<std::size_t> tail_{0};  // next slot to read (consumer)
  alignas(64) std::atomic<uint64_t> dropped_{0};
};

// A live source fed by another thread (tablet reader, window event loop, OSC server) through
// a ring: the producer calls ring().push(), the consumer polls.
class RingStrokeSource : public StrokeSource {
 public:
  explicit RingStrokeSource(std::string description, std::size_t capacity = 1024)
      : ring_(capacity), description_(std::move(description)) {}
  StrokeRing& ring() { return ring_; }
  std::size_t poll(double, std::span<StrokeSample> out) override { return ring_.pop_many(out); }
  std::string describe() const override { return description_; }

 private:
  StrokeRing ring_;
  std::string description_;
};

// Plays recorded samples back in real time: a sample recorded at time t (relative to the
// first sample) is due once poll's `now` reaches t. With loop = true the recording repeats
// forever after `loop_gap` seconds of silence (the kiosk attract mode), each pass shifted in
// time so that times stay monotonic.
class ReplayStrokeSource : public StrokeSource {
 public:
  ReplayStrokeSource(std::vector<StrokeSample> samples, std::string description, bool loop = false,
                     double loop_gap = 2.0);
  std::size_t poll(double now, std::span<StrokeSample> out) override;
  bool finished() const override;
  std::string describe() const override { return description_; }
  // Back to the first sample; the next poll's `now` counts from `now`.
  void restart(double now);
  double duration() const { return duration_; }

 private:
  std::vector<StrokeSample> samples_;
  std::string description_;
  bool loop_;
  double loop_gap_;
  double t0_ = 0;        // recording time of samples_[0]
  double duration_ = 0;  // last - first sample time
  double origin_ = 0;    // consumer time at which the current pass started
  std::size_t next_ = 0;
};

}  // namespace ardcell
