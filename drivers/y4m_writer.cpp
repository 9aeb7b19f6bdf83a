#include "drivers/y4m_writer.h"

#include <cmath>

namespace ardcell {
namespace {

uint8_t clamp_byte(double v) {
  v = std::round(v);
  return uint8_t(v < 0 ? 0 : (v > 255 ? 255 : v));
}

}  // namespace

void rgb_to_ycbcr601(uint8_t r, uint8_t g, uint8_t b, uint8_t& y, uint8_t& cb, uint8_t& cr) {
  // ITU-R BT.601: Y' = 16 + 219 (0.299 R + 0.587 G + 0.114 B) / 255, and Cb, Cr scaled by 224.
  const double R = r, G = g, B = b;
  y = clamp_byte(16.0 + (65.481 * R + 128.553 * G + 24.966 * B) / 255.0);
  cb = clamp_byte(128.0 + (-37.797 * R - 74.203 * G + 112.0 * B) / 255.0);
  cr = clamp_byte(128.0 + (112.0 * R - 93.786 * G - 18.214 * B) / 255.0);
}

std::string y4m_stream_header(int width, int height, int fps, Y4mChroma chroma) {
  return "YUV4MPEG2 W" + std::to_string(width) + " H" + std::to_string(height) + " F" +
         std::to_string(fps) + ":1 Ip A1:1 " + (chroma == Y4mChroma::k420 ? "C420jpeg" : "C444") +
         "\n";
}

std::size_t y4m_frame_bytes(int width, int height, Y4mChroma chroma) {
  const std::size_t luma = std::size_t(width) * std::size_t(height);
  const std::size_t chroma_plane =
      chroma == Y4mChroma::k420 ? std::size_t(width / 2) * std::size_t(height / 2) : luma;
  return luma + 2 * chroma_plane;
}

void y4m_convert_frame(const ImageRgb8& image, Y4mChroma chroma, std::vector<uint8_t>& planes) {
  const int w = image.width, h = image.height;
  const std::size_t luma = std::size_t(w) * std::size_t(h);
  uint8_t* Y = planes.data();
  if (chroma == Y4mChroma::k444) {
    uint8_t* Cb = Y + luma;
    uint8_t* Cr = Cb + luma;
    for (int y = 0; y < h; ++y) {
      const uint8_t* p = image.row(y);
      for (int x = 0; x < w; ++x, p += 3) {
        const std::size_t i = std::size_t(y) * w + x;
        rgb_to_ycbcr601(p[0], p[1], p[2], Y[i], Cb[i], Cr[i]);
      }
    }
    return;
  }
  const int cw = w / 2;
  uint8_t* Cb = Y + luma;
  uint8_t* Cr = Cb + std::size_t(cw) * std::size_t(h / 2);
  for (int y = 0; y < h; y += 2) {
    for (int x = 0; x < w; x += 2) {
      int sum_cb = 0, sum_cr = 0;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const uint8_t* p = image.row(y + dy) + 3 * (x + dx);
          uint8_t cb, cr;
          rgb_to_ycbcr601(p[0], p[1], p[2], Y[std::size_t(y + dy) * w + x + dx], cb, cr);
          sum_cb += cb;
          sum_cr += cr;
        }
      const std::size_t c = std::size_t(y / 2) * cw + x / 2;
      Cb[c] = uint8_t((sum_cb + 2) / 4);
      Cr[c] = uint8_t((sum_cr + 2) / 4);
    }
  }
}

Y4mFileSink::Y4mFileSink(std::filesystem::path path, int width, int height, int fps)
    : path_(std::move(path)),
      width_(width),
      height_(height),
      fps_(fps),
      chroma_(y4m_chroma_for(width, height)),
      planes_(y4m_frame_bytes(width, height, chroma_)) {}

Status Y4mFileSink::write(const ImageRgb8& image, const FrameInfo&) {
  if (image.width != width_ || image.height != height_)
    return Status::error(path_.string() + ": frame size changed within one video");
  if (!file_.is_open()) {
    if (Status s = file_.open(path_); !s) return s;
    const std::string header = y4m_stream_header(width_, height_, fps_, chroma_);
    file_.write(header.data(), header.size());
  }
  y4m_convert_frame(image, chroma_, planes_);
  static constexpr char kFrame[] = "FRAME\n";
  file_.write(kFrame, sizeof kFrame - 1);
  if (!file_.write(planes_.data(), planes_.size()))
    return Status::error(path_.string() + ": write failed");
  return Status::ok();
}

Status Y4mFileSink::finish() {
  if (!file_.is_open()) {  // no frame was written: an empty stream is still a valid file
    if (Status s = file_.open(path_); !s) return s;
    const std::string header = y4m_stream_header(width_, height_, fps_, chroma_);
    file_.write(header.data(), header.size());
  }
  return file_.commit();
}

}  // namespace ardcell
