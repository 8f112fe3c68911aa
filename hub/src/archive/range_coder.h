// The adaptive binary range coder of the .mca archive's blocks (format version 2), written for
// this project after LZMA's scheme (11-bit probabilities adapting by 1/32 per bit, 32-bit range,
// 64-bit low with carry propagation) because the console's Web Worker must decode it without a
// library: hub/web/js/archive_range_decoder.js is the same decoder in JavaScript.
// Integers are binarised as: zero flag, sign, the exponent n = floor(log2 |v|) in unary (each
// position its own adaptive bit), the highest of the n mantissa bits adaptive per n, the rest at
// probability 1/2. An IntModel holds one such set of adaptive bits; a stream picks its models by
// context so that each learns its own statistics.
// Errors: the decoder throws std::runtime_error "<field>: <reason>"; the archive reader prefixes
// the source. It never reads outside the span it was given.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace mocap {

// Largest magnitude an integer may have: exponents up to 28.
constexpr int32_t kMaxRangeCodedInteger = (int32_t{1} << 29) - 1;

struct IntModel {
  IntModel();
  uint16_t zero, sign;
  std::array<uint16_t, 30> exponent;
  std::array<uint16_t, 30> top;
};

class RangeEncoder {
 public:
  void Bit(uint16_t& probability, int bit);
  void Direct(uint32_t value, int bits);
  // |value| <= kMaxRangeCodedInteger (the caller's check).
  void Int(IntModel& model, int32_t value);
  void Float(float value);
  // Flushes and returns the bytes; the encoder is spent.
  std::string Finish();

 private:
  void ShiftLow();
  void Normalise();
  uint64_t low_ = 0;
  uint32_t range_ = 0xffffffffu;
  uint8_t cache_ = 0;
  uint64_t cache_size_ = 1;
  std::string out_;
};

class RangeDecoder {
 public:
  // Reads the first 5 bytes of [data, data + size); the first must be 0 (as the encoder writes).
  RangeDecoder(const uint8_t* data, size_t size);
  int Bit(uint16_t& probability);
  uint32_t Direct(int bits);
  int32_t Int(IntModel& model, const char* field);
  float Float();
  // Bytes read so far (a well-formed stream is read exactly to its end).
  size_t Consumed() const { return pos_; }

 private:
  uint8_t Next();
  void Normalise();
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  uint32_t range_ = 0xffffffffu;
  uint32_t code_ = 0;
};

}  // namespace mocap
