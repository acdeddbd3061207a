#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sim/render/render_error.h"

namespace incise::render {

// libturbojpeg rejected an image; what() carries its message.
class JpegError : public RenderError {
 public:
  explicit JpegError(const std::string& what) : RenderError(what) {}
};

// An 8-bit RGB image, rows from the top down, width * height * 3 bytes.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
};

// Frees a libturbojpeg handle (tjhandle) when its owner goes.
struct TurbojpegHandleDeleter {
  void operator()(void* handle) const;
};

// Encodes frames with one libturbojpeg compressor kept for the encoder's life, so that a stream
// of frames does not set one up per frame. Not thread-safe: one encoder per streaming thread.
class JpegEncoder {
 public:
  JpegEncoder();  // throws JpegError if libturbojpeg cannot start a compressor

  // rgb: width * height * 3 bytes, top row first; quality: 1 (smallest) .. 100 (best).
  // Chroma is subsampled 4:2:0, the usual choice for video-like streams.
  // Throws std::invalid_argument for sizes outside 1..8192, a buffer of the wrong length or a
  // quality outside 1..100; JpegError if compression fails.
  std::vector<std::uint8_t> encode(std::span<const std::uint8_t> rgb, int width, int height,
                                   int quality);
  // The same into jpeg, which is overwritten. A caller that keeps jpeg (and this encoder) from
  // frame to frame of one size allocates nothing per frame.
  void encode(std::span<const std::uint8_t> rgb, int width, int height, int quality,
              std::vector<std::uint8_t>& jpeg);

 private:
  std::unique_ptr<void, TurbojpegHandleDeleter> handle_;
  // Worst-case output buffer for the last size (tjBufSize), compressed into without reallocation
  // and then copied out: cheaper per frame than growing the caller's vector to the worst case.
  std::vector<std::uint8_t> scratch_;
};

// One-off encode with a temporary JpegEncoder; see JpegEncoder::encode.
std::vector<std::uint8_t> encode_jpeg(std::span<const std::uint8_t> rgb, int width, int height,
                                      int quality);

// Decodes a JPEG into RGB. Throws JpegError for data that is not a decodable JPEG.
RgbImage decode_jpeg(std::span<const std::uint8_t> jpeg);

}  // namespace incise::render
