// The adaptive binary range coder (see range_coder.h).
#include "archive/range_coder.h"

#include <cstring>
#include <stdexcept>

namespace mocap {
namespace {

constexpr int kProbabilityBits = 11;
constexpr uint16_t kHalf = 1 << (kProbabilityBits - 1);
constexpr int kAdaptShift = 5;
constexpr uint32_t kTop = 1u << 24;

}  // namespace

IntModel::IntModel() : zero(kHalf), sign(kHalf) {
  exponent.fill(kHalf);
  top.fill(kHalf);
}

void RangeEncoder::ShiftLow() {
  if (static_cast<uint32_t>(low_) < 0xff000000u || (low_ >> 32) != 0) {
    const uint8_t carry = static_cast<uint8_t>(low_ >> 32);
    uint8_t pending = cache_;
    do {
      out_.push_back(static_cast<char>(static_cast<uint8_t>(pending + carry)));
      pending = 0xff;
    } while (--cache_size_ != 0);
    cache_ = static_cast<uint8_t>(low_ >> 24);
  }
  ++cache_size_;
  low_ = (low_ & 0x00ffffffu) << 8;
}

void RangeEncoder::Normalise() {
  while (range_ < kTop) {
    range_ <<= 8;
    ShiftLow();
  }
}

void RangeEncoder::Bit(uint16_t& probability, int bit) {
  const uint32_t bound = (range_ >> kProbabilityBits) * probability;
  if (bit == 0) {
    range_ = bound;
    probability = static_cast<uint16_t>(probability + (((1u << kProbabilityBits) - probability) >> kAdaptShift));
  } else {
    low_ += bound;
    range_ -= bound;
    probability = static_cast<uint16_t>(probability - (probability >> kAdaptShift));
  }
  Normalise();
}

void RangeEncoder::Direct(uint32_t value, int bits) {
  for (int i = bits - 1; i >= 0; --i) {
    range_ >>= 1;
    if ((value >> i) & 1u) low_ += range_;
    Normalise();
  }
}

void RangeEncoder::Int(IntModel& model, int32_t value) {
  Bit(model.zero, value != 0);
  if (value == 0) return;
  Bit(model.sign, value < 0);
  const uint32_t magnitude = static_cast<uint32_t>(value < 0 ? -static_cast<int64_t>(value) : value);
  int n = 0;
  while ((magnitude >> (n + 1)) != 0) ++n;
  for (int i = 0; i < n; ++i) Bit(model.exponent[static_cast<size_t>(i)], 1);
  Bit(model.exponent[static_cast<size_t>(n)], 0);
  if (n == 0) return;
  Bit(model.top[static_cast<size_t>(n)], static_cast<int>((magnitude >> (n - 1)) & 1u));
  Direct(magnitude, n - 1);
}

void RangeEncoder::Float(float value) {
  uint32_t raw;
  std::memcpy(&raw, &value, sizeof(raw));
  Direct(raw, 32);
}

std::string RangeEncoder::Finish() {
  for (int i = 0; i < 5; ++i) ShiftLow();
  return std::move(out_);
}

RangeDecoder::RangeDecoder(const uint8_t* data, size_t size) : data_(data), size_(size) {
  if (Next() != 0) throw std::runtime_error("range coder: the first byte is not 0");
  for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | Next();
}

uint8_t RangeDecoder::Next() {
  if (pos_ >= size_) throw std::runtime_error("range coder: the coded data ends early");
  return data_[pos_++];
}

void RangeDecoder::Normalise() {
  while (range_ < kTop) {
    range_ <<= 8;
    code_ = (code_ << 8) | Next();
  }
}

int RangeDecoder::Bit(uint16_t& probability) {
  const uint32_t bound = (range_ >> kProbabilityBits) * probability;
  int bit;
  if (code_ < bound) {
    range_ = bound;
    probability = static_cast<uint16_t>(probability + (((1u << kProbabilityBits) - probability) >> kAdaptShift));
    bit = 0;
  } else {
    code_ -= bound;
    range_ -= bound;
    probability = static_cast<uint16_t>(probability - (probability >> kAdaptShift));
    bit = 1;
  }
  Normalise();
  return bit;
}

uint32_t RangeDecoder::Direct(int bits) {
  uint32_t value = 0;
  for (int i = 0; i < bits; ++i) {
    range_ >>= 1;
    const uint32_t bit = code_ >= range_ ? 1u : 0u;
    if (bit) code_ -= range_;
    value = (value << 1) | bit;
    Normalise();
  }
  return value;
}

int32_t RangeDecoder::Int(IntModel& model, const char* field) {
  if (!Bit(model.zero)) return 0;
  const bool negative = Bit(model.sign) != 0;
  int n = 0;
  while (Bit(model.exponent[static_cast<size_t>(n)])) {
    if (++n > 28) throw std::runtime_error(std::string(field) + ": a value past +-(2^29 - 1)");
  }
  uint32_t magnitude = 1;
  if (n > 0) {
    magnitude = (magnitude << 1) | static_cast<uint32_t>(Bit(model.top[static_cast<size_t>(n)]));
    magnitude = (magnitude << (n - 1)) | Direct(n - 1);
  }
  return negative ? -static_cast<int32_t>(magnitude) : static_cast<int32_t>(magnitude);
}

float RangeDecoder::Float() {
  const uint32_t raw = Direct(32);
  float value;
  std::memcpy(&value, &raw, sizeof(value));
  return value;
}

}  // namespace mocap
