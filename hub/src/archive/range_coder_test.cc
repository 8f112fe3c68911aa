// The range coder: integers of every size (0, +-1, powers of two and their neighbours, the
// largest allowed) and floats come back exactly, mixed with adaptive and plain bits; the
// decoder reads exactly the encoder's bytes; skewed data costs far less than a byte a value;
// truncated streams, a nonzero first byte and exponents past 28 are refused.
#include "archive/range_coder.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace mocap {
namespace {

std::vector<int32_t> TestIntegers() {
  std::vector<int32_t> values = {0, 1, -1, 2, -2, 3, kMaxRangeCodedInteger, -kMaxRangeCodedInteger};
  for (int n = 1; n < 29; ++n)
    for (int32_t v : {(int32_t{1} << n) - 1, int32_t{1} << n, (int32_t{1} << n) + 1}) {
      values.push_back(v);
      values.push_back(-v);
    }
  std::mt19937 random(7);
  std::geometric_distribution<int32_t> small(0.4);
  for (int i = 0; i < 5000; ++i) values.push_back(small(random) * (i % 2 ? 1 : -1));
  return values;
}

TEST(RangeCoder, IntegersFloatsAndBitsComeBackExactly) {
  const std::vector<int32_t> values = TestIntegers();
  const std::vector<float> floats = {0.0f, 1.5f, -3.25e-7f, 1e30f, std::nextafter(1.0f, 2.0f)};
  RangeEncoder encoder;
  IntModel a, b;
  uint16_t flag = 1024;
  for (size_t i = 0; i < values.size(); ++i) {
    encoder.Int(i % 3 ? a : b, values[i]);
    encoder.Bit(flag, static_cast<int>(i % 5 == 0));
  }
  for (float f : floats) encoder.Float(f);
  encoder.Direct(0x2a5, 10);
  const std::string bytes = encoder.Finish();

  RangeDecoder decoder(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  IntModel da, db;
  uint16_t dflag = 1024;
  for (size_t i = 0; i < values.size(); ++i) {
    ASSERT_EQ(decoder.Int(i % 3 ? da : db, "v"), values[i]) << i;
    ASSERT_EQ(decoder.Bit(dflag), static_cast<int>(i % 5 == 0)) << i;
  }
  for (float f : floats) EXPECT_EQ(decoder.Float(), f);
  EXPECT_EQ(decoder.Direct(10), 0x2a5u);
  EXPECT_EQ(decoder.Consumed(), bytes.size());
}

TEST(RangeCoder, SkewedIntegersCostLittle) {
  RangeEncoder encoder;
  IntModel model;
  for (int i = 0; i < 10000; ++i) encoder.Int(model, i % 20 == 0 ? 1 : 0);
  // About 0.29 bits a value for a 1-in-20 event; a varint would take 8.
  EXPECT_LT(encoder.Finish().size(), 10000u / 16);
}

TEST(RangeCoder, TruncationsAndBadStartsAreRefused) {
  RangeEncoder encoder;
  IntModel model;
  for (int i = 0; i < 200; ++i) encoder.Int(model, i * 37 - 3000);
  const std::string bytes = encoder.Finish();
  for (size_t length = 0; length < bytes.size(); ++length) {
    EXPECT_THROW(
        {
          RangeDecoder decoder(reinterpret_cast<const uint8_t*>(bytes.data()), length);
          IntModel again;
          for (int i = 0; i < 200; ++i) decoder.Int(again, "v");
        },
        std::runtime_error)
        << length;
  }
  std::string bad = bytes;
  bad[0] = 1;
  EXPECT_THROW(RangeDecoder(reinterpret_cast<const uint8_t*>(bad.data()), bad.size()), std::runtime_error);
  // Every adaptive bit 1: the exponent's unary code runs past 28.
  const std::string ones = std::string(1, '\0') + std::string(64, '\xff');
  RangeDecoder decoder(reinterpret_cast<const uint8_t*>(ones.data()), ones.size());
  IntModel again;
  EXPECT_THROW(decoder.Int(again, "v"), std::runtime_error);
}

}  // namespace
}  // namespace mocap
