#include "sim/render/jpeg.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>

namespace incise::render {
namespace {

// Four flat quadrants on 16-pixel boundaries (the 4:2:0 block size), so that colour must survive
// compression almost unchanged.
RgbImage quadrants(int width, int height) {
  const std::uint8_t colours[4][3] = {{200, 40, 40}, {40, 180, 60}, {30, 60, 210}, {230, 220, 90}};
  RgbImage image{width, height, std::vector<std::uint8_t>(width * height * 3)};
  for (int row = 0; row < height; ++row) {
    for (int column = 0; column < width; ++column) {
      const int quadrant = (row < height / 2 ? 0 : 2) + (column < width / 2 ? 0 : 1);
      for (int channel = 0; channel < 3; ++channel) {
        image.rgb[(row * width + column) * 3 + channel] = colours[quadrant][channel];
      }
    }
  }
  return image;
}

TEST(Jpeg, RoundTripKeepsSizeAndColours) {
  const RgbImage original = quadrants(64, 48);
  const std::vector<std::uint8_t> jpeg = encode_jpeg(original.rgb, 64, 48, 90);
  ASSERT_GE(jpeg.size(), 4u);
  EXPECT_EQ(jpeg[0], 0xFF);  // SOI marker
  EXPECT_EQ(jpeg[1], 0xD8);
  EXPECT_EQ(jpeg[jpeg.size() - 2], 0xFF);  // EOI marker
  EXPECT_EQ(jpeg[jpeg.size() - 1], 0xD9);
  EXPECT_LT(jpeg.size(), original.rgb.size());

  const RgbImage decoded = decode_jpeg(jpeg);
  EXPECT_EQ(decoded.width, 64);
  EXPECT_EQ(decoded.height, 48);
  ASSERT_EQ(decoded.rgb.size(), original.rgb.size());
  // Away from the quadrant edges, flat blocks at quality 90 come back within a few levels
  // (YCbCr rounding only). Next to an edge the decoder's smooth chroma upsampling blends the two
  // colours, as a browser's decoder does too, so there only the mean error is bounded.
  double total_error = 0.0;
  for (int row = 0; row < 48; ++row) {
    for (int column = 0; column < 64; ++column) {
      const bool near_edge = std::abs(row + 0.5 - 24) < 3 || std::abs(column + 0.5 - 32) < 3;
      for (int channel = 0; channel < 3; ++channel) {
        const std::size_t i = (row * 64 + column) * 3 + channel;
        const int error = std::abs(decoded.rgb[i] - original.rgb[i]);
        total_error += error;
        if (!near_edge) {
          ASSERT_LE(error, 4) << "row " << row << " column " << column;
        }
      }
    }
  }
  EXPECT_LT(total_error / original.rgb.size(), 3.0);
}

TEST(Jpeg, EncoderIsReusableAndDeterministic) {
  JpegEncoder encoder;
  const RgbImage first = quadrants(32, 32);
  const RgbImage second = quadrants(48, 16);
  const std::vector<std::uint8_t> a = encoder.encode(first.rgb, 32, 32, 75);
  const std::vector<std::uint8_t> b = encoder.encode(second.rgb, 48, 16, 75);
  EXPECT_EQ(encoder.encode(first.rgb, 32, 32, 75), a);
  EXPECT_EQ(b, encode_jpeg(second.rgb, 48, 16, 75));
  EXPECT_EQ(decode_jpeg(b).width, 48);
}

// The overload that writes into the caller's vector gives the same bytes, replaces whatever the
// vector held, and keeps its storage when it has room.
TEST(Jpeg, EncodeIntoCallersVectorOverwritesIt) {
  JpegEncoder encoder;
  const RgbImage image = quadrants(64, 48);
  std::vector<std::uint8_t> jpeg(100000, 0xAB);
  const std::uint8_t* storage = jpeg.data();
  encoder.encode(image.rgb, 64, 48, 80, jpeg);
  EXPECT_EQ(jpeg, encoder.encode(image.rgb, 64, 48, 80));
  EXPECT_EQ(jpeg.data(), storage);
  EXPECT_EQ(decode_jpeg(jpeg).width, 64);
  EXPECT_THROW(encoder.encode(image.rgb, 64, 47, 80, jpeg), std::invalid_argument);
}

TEST(Jpeg, LowerQualityGivesSmallerFiles) {
  RgbImage noise{64, 64, std::vector<std::uint8_t>(64 * 64 * 3)};
  std::uint32_t state = 12345;  // fixed LCG: the test must not depend on a random seed
  for (std::uint8_t& byte : noise.rgb) {
    state = state * 1664525u + 1013904223u;
    byte = static_cast<std::uint8_t>(state >> 24);
  }
  EXPECT_LT(encode_jpeg(noise.rgb, 64, 64, 20).size(), encode_jpeg(noise.rgb, 64, 64, 95).size());
}

TEST(Jpeg, RejectsInvalidInput) {
  const std::vector<std::uint8_t> pixel(3, 0);
  EXPECT_THROW(encode_jpeg(pixel, 0, 1, 80), std::invalid_argument);
  EXPECT_THROW(encode_jpeg(pixel, 1, 0, 80), std::invalid_argument);
  EXPECT_THROW(encode_jpeg(pixel, 8193, 1, 80), std::invalid_argument);
  EXPECT_THROW(encode_jpeg(pixel, 2, 1, 80), std::invalid_argument);  // buffer too short
  EXPECT_THROW(encode_jpeg(pixel, 1, 1, 0), std::invalid_argument);
  EXPECT_THROW(encode_jpeg(pixel, 1, 1, 101), std::invalid_argument);
  try {
    encode_jpeg(pixel, 0, 1, 80);
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "JPEG size 0x1 is invalid: width and height must be 1..8192");
  }
  EXPECT_NO_THROW(encode_jpeg(pixel, 1, 1, 1));
}

TEST(Jpeg, DecodingGarbageThrowsJpegError) {
  const std::vector<std::uint8_t> garbage = {1, 2, 3, 4, 5, 6, 7, 8};
  EXPECT_THROW(decode_jpeg(garbage), JpegError);
}

}  // namespace
}  // namespace incise::render
