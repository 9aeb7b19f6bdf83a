#pragma once
// YUV4MPEG2 (.y4m) video, built in: the uncompressed format every video tool reads (ffmpeg,
// mpv, x264). RGB is converted to BT.601 limited-range Y'CbCr; 4:2:0 (chroma averaged over 2x2
// pixels, "C420jpeg") when both sides are even, else 4:4:4 ("C444").
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "host/io/atomic_file.h"
#include "host/render/frame_sink.h"

namespace ardcell {

enum class Y4mChroma : uint8_t { k420, k444 };

// The 4:2:0 layout needs even sides.
inline Y4mChroma y4m_chroma_for(int width, int height) {
  return width % 2 == 0 && height % 2 == 0 ? Y4mChroma::k420 : Y4mChroma::k444;
}

// BT.601 limited range (Y' 16..235, Cb/Cr 16..240) from 8-bit R'G'B'.
void rgb_to_ycbcr601(uint8_t r, uint8_t g, uint8_t b, uint8_t& y, uint8_t& cb, uint8_t& cr);

// "YUV4MPEG2 W<w> H<h> F<fps>:1 Ip A1:1 C420jpeg\n"
std::string y4m_stream_header(int width, int height, int fps, Y4mChroma chroma);

// Converts one frame to planar Y'CbCr (Y plane, then Cb, then Cr) into `planes`, whose size
// must be y4m_frame_bytes(...); allocates nothing.
std::size_t y4m_frame_bytes(int width, int height, Y4mChroma chroma);
void y4m_convert_frame(const ImageRgb8& image, Y4mChroma chroma, std::vector<uint8_t>& planes);

class Y4mFileSink : public FrameSink {
 public:
  // The file appears at `path` on finish(); until then it is a temporary sibling.
  Y4mFileSink(std::filesystem::path path, int width, int height, int fps);
  Status write(const ImageRgb8& image, const FrameInfo& info) override;
  Status finish() override;
  std::string describe() const override { return path_.string(); }

 private:
  std::filesystem::path path_;
  int width_, height_, fps_;
  Y4mChroma chroma_;
  AtomicFile file_;
  std::vector<uint8_t> planes_;
};

}  // namespace ardcell
