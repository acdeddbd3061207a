#include "sim/render/jpeg.h"

#include <turbojpeg.h>

#include <cstddef>
#include <stdexcept>
#include <string>

namespace incise::render {
namespace {

// Matches Framebuffer::max_size: frames come from framebuffers.
constexpr int max_side = 8192;

std::string turbojpeg_message(tjhandle handle) {
  return tjGetErrorStr2(handle);
}

}  // namespace

void TurbojpegHandleDeleter::operator()(void* handle) const {
  tjDestroy(handle);
}

JpegEncoder::JpegEncoder() : handle_(tjInitCompress()) {
  if (handle_ == nullptr) {
    throw JpegError("tjInitCompress failed: " + turbojpeg_message(nullptr));
  }
}

std::vector<std::uint8_t> JpegEncoder::encode(std::span<const std::uint8_t> rgb, int width,
                                              int height, int quality) {
  std::vector<std::uint8_t> jpeg;
  encode(rgb, width, height, quality, jpeg);
  return jpeg;
}

void JpegEncoder::encode(std::span<const std::uint8_t> rgb, int width, int height, int quality,
                         std::vector<std::uint8_t>& jpeg) {
  if (width < 1 || width > max_side || height < 1 || height > max_side) {
    throw std::invalid_argument(
        "JPEG size " + std::to_string(width) + "x" + std::to_string(height) +
        " is invalid: width and height must be 1.." + std::to_string(max_side));
  }
  const std::size_t expected = static_cast<std::size_t>(width) * height * 3;
  if (rgb.size() != expected) {
    throw std::invalid_argument("JPEG input has " + std::to_string(rgb.size()) + " bytes, " +
                                std::to_string(width) + "x" + std::to_string(height) +
                                " RGB needs " + std::to_string(expected));
  }
  if (quality < 1 || quality > 100) {
    throw std::invalid_argument("JPEG quality " + std::to_string(quality) + " is not in 1..100");
  }

  // tjBufSize is the worst case for any content, so compressing in place never reallocates.
  scratch_.resize(tjBufSize(width, height, TJSAMP_420));
  unsigned char* output = scratch_.data();
  unsigned long size = scratch_.size();
  if (tjCompress2(handle_.get(), rgb.data(), width, 0, height, TJPF_RGB, &output, &size, TJSAMP_420,
                  quality, TJFLAG_NOREALLOC) != 0) {
    throw JpegError("tjCompress2 failed: " + turbojpeg_message(handle_.get()));
  }
  jpeg.assign(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(size));
}

std::vector<std::uint8_t> encode_jpeg(std::span<const std::uint8_t> rgb, int width, int height,
                                      int quality) {
  return JpegEncoder().encode(rgb, width, height, quality);
}

RgbImage decode_jpeg(std::span<const std::uint8_t> jpeg) {
  const std::unique_ptr<void, TurbojpegHandleDeleter> handle(tjInitDecompress());
  if (handle == nullptr) {
    throw JpegError("tjInitDecompress failed: " + turbojpeg_message(nullptr));
  }
  // libturbojpeg takes a non-const pointer but does not write through it.
  auto* data = const_cast<unsigned char*>(jpeg.data());
  RgbImage image;
  int subsampling = 0;
  int colourspace = 0;
  if (tjDecompressHeader3(handle.get(), data, jpeg.size(), &image.width, &image.height,
                          &subsampling, &colourspace) != 0) {
    throw JpegError("tjDecompressHeader3 failed: " + turbojpeg_message(handle.get()));
  }
  image.rgb.resize(static_cast<std::size_t>(image.width) * image.height * 3);
  if (tjDecompress2(handle.get(), data, jpeg.size(), image.rgb.data(), image.width, 0, image.height,
                    TJPF_RGB, 0) != 0) {
    throw JpegError("tjDecompress2 failed: " + turbojpeg_message(handle.get()));
  }
  return image;
}

}  // namespace incise::render
