#pragma once
// PNG output (libpng): one RGB8, 8-bit or 16-bit grayscale image per file, written under a
// temporary name and renamed (never a half-written file), and a FrameSink that writes a numbered
// sequence (<dir>/<prefix>_<step>.png).
#include <filesystem>
#include <string>

#include "host/config/status.h"
#include "host/render/frame_sink.h"
#include "host/render/image.h"
#include "host/render/texture_maps.h"

namespace ardcell {

// compression_level: zlib level 0..9 (1-3 are fast and only a little larger than 6).
Status write_png(const std::filesystem::path& path, const ImageRgb8& image,
                 int compression_level = 3);
// Grayscale height maps (host/render/texture_maps.h); 16-bit samples are stored big-endian, as
// PNG requires, whatever the host's byte order.
Status write_png_gray8(const std::filesystem::path& path, const ImageGray8& image,
                       int compression_level = 3);
Status write_png_gray16(const std::filesystem::path& path, const ImageGray16& image,
                        int compression_level = 3);

class PngSequenceSink : public FrameSink {
 public:
  // Files <dir>/<prefix>_<step, 8 digits>.png; dir must exist.
  PngSequenceSink(std::filesystem::path dir, std::string prefix)
      : dir_(std::move(dir)), prefix_(std::move(prefix)) {}
  Status write(const ImageRgb8& image, const FrameInfo& info) override;
  Status finish() override { return Status::ok(); }
  std::string describe() const override;
  std::filesystem::path path_for(int64_t step) const;

 private:
  std::filesystem::path dir_;
  std::string prefix_;
};

}  // namespace ardcell
