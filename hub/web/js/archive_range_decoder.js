// The .mca archive's adaptive binary range decoder (hub/src/archive/range_coder.h, the same
// scheme bit for bit: 11-bit probabilities adapting by 1/32, 32-bit range; integers as zero flag,
// sign, unary exponent, adaptive top mantissa bit, plain lower bits). Errors throw Error.

const PROBABILITY_BITS = 11;
const HALF = 1 << (PROBABILITY_BITS - 1);
const TOP = 2 ** 24;

// An integer's adaptive probabilities in one array: zero flag, sign, 30 exponent bits, 30 top
// mantissa bits (the C++ IntModel's fields in order).
const ZERO = 0, SIGN = 1, EXPONENT = 2, TOP_BIT = 32;
export function newIntModel() {
  return new Uint16Array(62).fill(HALF);
}

// A single adaptive bit.
export function newBitModel() {
  return new Uint16Array(1).fill(HALF);
}

export class RangeDecoder {
  // bytes: Uint8Array holding exactly the coded stream.
  constructor(bytes) {
    this.bytes = bytes;
    this.pos = 0;
    this.range = 0xffffffff;
    this.code = 0;
    if (this.next() !== 0) throw new Error('range coder: the first byte is not 0');
    for (let i = 0; i < 4; ++i) this.code = (this.code * 256 + this.next()) >>> 0;
  }

  next() {
    if (this.pos >= this.bytes.length) throw new Error('range coder: the coded data ends early');
    return this.bytes[this.pos++];
  }

  normalise() {
    while (this.range < TOP) {
      this.range = (this.range * 256) >>> 0;
      this.code = ((this.code * 256) >>> 0) + this.next();
      this.code >>>= 0;
    }
  }

  // probabilities: a Uint16Array and the index of the bit's probability in it.
  bit(holder, key) {
    const p = holder[key];
    const bound = (this.range >>> PROBABILITY_BITS) * p;
    let bit;
    if (this.code < bound) {
      this.range = bound;
      holder[key] = p + (((1 << PROBABILITY_BITS) - p) >> 5);
      bit = 0;
    } else {
      this.code = (this.code - bound) >>> 0;
      this.range = (this.range - bound) >>> 0;
      holder[key] = p - (p >> 5);
      bit = 1;
    }
    this.normalise();
    return bit;
  }

  direct(bits) {
    let value = 0;
    for (let i = 0; i < bits; ++i) {
      this.range >>>= 1;
      let bit = 0;
      if (this.code >= this.range) { this.code = (this.code - this.range) >>> 0; bit = 1; }
      value = value * 2 + bit;
      this.normalise();
    }
    return value;
  }

  int(model, field) {
    if (!this.bit(model, ZERO)) return 0;
    const negative = this.bit(model, SIGN);
    let n = 0;
    while (this.bit(model, EXPONENT + n)) {
      if (++n > 28) throw new Error(`${field}: a value past +-(2^29 - 1)`);
    }
    let magnitude = 1;
    if (n > 0) {
      magnitude = magnitude * 2 + this.bit(model, TOP_BIT + n);
      magnitude = magnitude * 2 ** (n - 1) + this.direct(n - 1);
    }
    return negative ? -magnitude : magnitude;
  }

  float() {
    const raw = this.direct(32);
    const view = new DataView(new ArrayBuffer(4));
    view.setUint32(0, raw, true);
    return view.getFloat32(0, true);
  }
}
