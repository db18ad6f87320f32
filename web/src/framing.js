// Length-delimited framing, as proto/wire/frame.h does it: each message is
// a varint32 length followed by that many bytes (protobuf's delimited
// format). Pure byte handling, no I/O: the WebSocket and the Node tests'
// TCP socket feed it alike. A WebSocket message need not hold whole frames,
// so FrameReader treats what arrives as one byte stream.

// The largest frame the viewer accepts from the server, in bytes: a FULL
// pose frame with velocities takes about 57 bytes a body, so 64 MiB holds
// the server's 100000 bodies at most several times over.
export const kMaxFrameBytes = 64 * 1024 * 1024;

// A varint32 takes at most 5 bytes.
const kMaxPrefixBytes = 5;

// `body` (a Uint8Array) with its varint length in front, as one Uint8Array.
export function encodeFrame(body) {
  const prefix = [];
  let n = body.length >>> 0;
  while (n >= 0x80) {
    prefix.push((n & 0x7f) | 0x80);
    n >>>= 7;
  }
  prefix.push(n);
  const out = new Uint8Array(prefix.length + body.length);
  out.set(prefix, 0);
  out.set(body, prefix.length);
  return out;
}

// The stream broke: a length prefix that is not a varint32, or a frame
// larger than allowed. Nothing after it can be trusted.
export class FramingError extends Error {}

// Splits a byte stream into frame bodies. push() what arrived, then call
// next() until it returns null.
export class FrameReader {
  constructor(maxFrameBytes = kMaxFrameBytes) {
    this.maxFrameBytes = maxFrameBytes;
    this.buffer = new Uint8Array(0);
    this.start = 0;  // offset of the first unconsumed byte
    this.end = 0;    // offset one past the last byte held
  }

  // Appends `chunk` (a Uint8Array), growing or compacting the buffer.
  push(chunk) {
    if (this.end + chunk.length > this.buffer.length) {
      const held = this.end - this.start;
      const capacity = Math.max(held + chunk.length, 2 * held, 4096);
      const grown = capacity > this.buffer.length ? new Uint8Array(capacity) : this.buffer;
      if (grown === this.buffer) {
        this.buffer.copyWithin(0, this.start, this.end);
      } else {
        grown.set(this.buffer.subarray(this.start, this.end), 0);
      }
      this.buffer = grown;
      this.start = 0;
      this.end = held;
    }
    this.buffer.set(chunk, this.end);
    this.end += chunk.length;
  }

  // The next whole frame body (a view valid until the next push()), or null
  // when the prefix or the body is not complete yet. Throws FramingError on
  // a broken stream.
  next() {
    let length = 0;
    let shift = 0;
    let i = this.start;
    for (;;) {
      if (i === this.end) return null;  // the prefix is not complete yet
      const byte = this.buffer[i++];
      length += (byte & 0x7f) * 2 ** shift;
      shift += 7;
      if ((byte & 0x80) === 0) break;
      if (i - this.start === kMaxPrefixBytes) throw new FramingError("a frame's length prefix is not a varint32");
    }
    if (length > this.maxFrameBytes) {
      throw new FramingError(`a frame of ${length} bytes is larger than the ${this.maxFrameBytes} allowed`);
    }
    if (this.end - i < length) return null;
    const body = this.buffer.subarray(i, i + length);
    this.start = i + length;
    return body;
  }

  // Bytes held that do not form a whole frame yet.
  bufferedBytes() {
    return this.end - this.start;
  }
}
