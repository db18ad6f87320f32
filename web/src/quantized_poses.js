// Decodes the `packed` bytes of a QUANTIZED or DELTA PoseFrame, the layout
// of proto/wire/quantized_poses.h (docs/protocol.md, "Pose encodings"):
//
//   varint n, varint flags (bit 0: velocities), varint k (step 2^-k m),
//   n zigzag varints of id differences, then for n > 0: 3 zigzag varints of
//   the origin cell, 3 bytes of bit widths, and a bit stream (least
//   significant bit first) per body: the cell offsets, 32 bits of smallest
//   three orientation, and with velocities 6 x 16-bit levels.
//
// Numbers stay exact: cells are within +-2^52 and offsets below 2^53, so
// plain doubles hold them; a varint beyond 2^53 is refused.

const kVelocitiesFlag = 1;
const kMaxWidth = 63;
const kVelocityBits = 16;
const kLinearVelocityStep = 1 / 128;   // m/s
const kAngularVelocityStep = 1 / 256;  // rad/s
const kZeroLevel = 511;                // smallest three: levels 0..1022
const kSqrt2 = Math.SQRT2;
const kMaxExact = 2 ** 53;

// `packed` does not follow the layout.
export class PackedPosesError extends Error {}

// Reads varints and bit fields from a Uint8Array.
class Reader {
  constructor(bytes) {
    this.bytes = bytes;
    this.at = 0;   // next byte
    this.bit = 0;  // next bit of the bit stream, from bit 0 of byte `at` where it began
  }

  varint(what) {
    let value = 0;
    let scale = 1;
    for (let i = 0; i < 10; ++i) {
      if (this.at >= this.bytes.length) throw new PackedPosesError(`${what}: the bytes end inside a varint`);
      const byte = this.bytes[this.at++];
      value += (byte & 0x7f) * scale;
      if (!(byte & 0x80)) {
        if (value > kMaxExact) throw new PackedPosesError(`${what}: ${value} is beyond 2^53`);
        return value;
      }
      scale *= 128;
    }
    throw new PackedPosesError(`${what}: a varint longer than 10 bytes`);
  }

  // The next `bits` bits (0 to 63) of the bit stream that starts at `start`.
  bits(start, bits) {
    let value = 0;
    let scale = 1;
    let done = 0;
    while (done < bits) {
      const index = start + (this.bit >> 3);
      if (index >= this.bytes.length) throw new PackedPosesError("the bodies' bit stream is cut short");
      const offset = this.bit & 7;
      const take = Math.min(bits - done, 8 - offset);
      value += ((this.bytes[index] >> offset) & ((1 << take) - 1)) * scale;
      scale *= 2 ** take;
      done += take;
      this.bit += take;
    }
    return value;
  }
}

const unzigzag = (value) => (value % 2 === 0 ? value / 2 : -(value + 1) / 2);

// The unit quaternion [w, x, y, z] of a smallest-three value (as
// proto/wire/smallest_three.cpp), written into out[at..at+3].
export function unpackSmallestThree(packed, out, at) {
  const largest = packed & 3;
  let squares = 0;
  let shift = 2;
  for (let k = 0; k < 4; ++k) {
    if (k === largest) continue;
    const level = Math.floor(packed / 2 ** shift) & 0x3ff;
    const c = (level - kZeroLevel) / (kZeroLevel * kSqrt2);
    out[at + k] = c;
    squares += c * c;
    shift += 10;
  }
  out[at + largest] = Math.sqrt(Math.max(0, 1 - squares));
  const norm = Math.sqrt(squares + out[at + largest] * out[at + largest]);
  for (let k = 0; k < 4; ++k) out[at + k] /= norm;
}

// The bodies of `packed` (a Uint8Array): {velocities, ids, positions (m, 3
// a body), orientations (w x y z, 4 a body), linearVelocities and
// angularVelocities (3 a body, empty without velocities)}, as Float64Arrays
// in the bodies' order. Throws PackedPosesError naming what is wrong.
export function decodePackedPoses(packed) {
  const reader = new Reader(packed);
  const count = reader.varint("body count");
  const flags = reader.varint("flags");
  const exponent = reader.varint("position step exponent");
  // Each body takes at least one byte of id.
  if (count > packed.length) throw new PackedPosesError(`body count ${count} exceeds the ${packed.length} bytes`);
  if (exponent > 64) throw new PackedPosesError(`position step exponent ${exponent} is over 64`);
  const velocities = (flags & kVelocitiesFlag) !== 0;
  const ids = new Array(count);
  let id = 0;
  for (let i = 0; i < count; ++i) {
    id += unzigzag(reader.varint("body id"));
    if (id < 0 || id > 0xffffffff) throw new PackedPosesError(`body id ${id} is not a uint32`);
    ids[i] = id;
  }
  const poses = {
    velocities,
    ids,
    positions: new Float64Array(3 * count),
    orientations: new Float64Array(4 * count),
    linearVelocities: new Float64Array(velocities ? 3 * count : 0),
    angularVelocities: new Float64Array(velocities ? 3 * count : 0),
  };
  if (count === 0) {
    if (reader.at !== packed.length) throw new PackedPosesError("bytes left over after an empty body list");
    return poses;
  }
  const origin = [0, 1, 2].map(() => unzigzag(reader.varint("origin cell")));
  if (reader.at + 3 > packed.length) throw new PackedPosesError("the bit widths are cut short");
  const width = [0, 1, 2].map((a) => packed[reader.at + a]);
  for (const w of width) if (w > kMaxWidth) throw new PackedPosesError(`a bit width of ${w} is over ${kMaxWidth}`);
  const start = reader.at + 3;
  const step = 2 ** -exponent;
  const level = (raw) => (raw >= 0x8000 ? raw - 0x10000 : raw);  // 16-bit two's complement
  for (let i = 0; i < count; ++i) {
    for (let a = 0; a < 3; ++a) poses.positions[3 * i + a] = (origin[a] + reader.bits(start, width[a])) * step;
    unpackSmallestThree(reader.bits(start, 32), poses.orientations, 4 * i);
    if (!velocities) continue;
    for (let a = 0; a < 3; ++a) poses.linearVelocities[3 * i + a] = level(reader.bits(start, kVelocityBits)) * kLinearVelocityStep;
    for (let a = 0; a < 3; ++a) poses.angularVelocities[3 * i + a] = level(reader.bits(start, kVelocityBits)) * kAngularVelocityStep;
  }
  // Only the padding of the last byte may remain.
  if (start + Math.ceil(reader.bit / 8) !== packed.length) {
    throw new PackedPosesError(`${packed.length - start - Math.ceil(reader.bit / 8)} bytes left over after the bodies`);
  }
  return poses;
}
