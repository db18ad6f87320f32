// Smooth motion between pose frames. The server sends a frame every
// period_ticks ticks; the page draws at the display's rate, about one frame
// period behind the newest tick it has, between the two frames around that
// moment: positions linearly, orientations by spherical interpolation.
//
// Ticks are the clock: TickClock maps the page's clock (ms) to the server's
// tick from the frames' arrival, and PoseBuffer keeps the last few frames
// and samples them at any tick.

// How many frames PoseBuffer keeps: enough to bridge a late frame or two.
const kFramesKept = 6;

// Estimates the server's current tick from when frames arrive.
export class TickClock {
  constructor() {
    this.offset = null;   // ticks: server tick - page time (ms) * rate / 1000
    this.rateHz = 0;      // the sim's tick rate
  }

  // The sim's tick rate changed (Welcome, Stats, Subscribed).
  setRate(rateHz) {
    if (rateHz > 0 && rateHz !== this.rateHz) {
      this.rateHz = rateHz;
      this.offset = null;  // the old offset was in the old rate's ticks
    }
  }

  // A frame of `tick` arrived at page time `nowMs`. The estimate follows
  // the arrivals slowly, so network jitter does not shake the picture, and
  // jumps when they disagree by more than `jumpTicks` (the world was paused,
  // stepped, or the page was in the background).
  observe(tick, nowMs, jumpTicks) {
    if (!(this.rateHz > 0)) return;
    const observed = tick - (nowMs * this.rateHz) / 1000;
    if (this.offset === null || Math.abs(observed - this.offset) > jumpTicks) {
      this.offset = observed;
    } else {
      this.offset += 0.05 * (observed - this.offset);
    }
  }

  // The server's tick now, as a real number; null before the first frame.
  tickAt(nowMs) {
    if (this.offset === null) return null;
    return this.offset + (nowMs * this.rateHz) / 1000;
  }
}

// The last few frames of one subscription, oldest first.
export class PoseBuffer {
  constructor() {
    this.frames = [];  // {tick, index: Map id -> i, positions, orientations}
  }

  clear() {
    this.frames = [];
  }

  // Adds a FULL PoseFrame. A frame whose tick is not newer than the last
  // (a Reset does not turn ticks back, so this only happens across
  // reconnects) starts the buffer afresh.
  push(frame) {
    const tick = Number(frame.tick);
    const last = this.frames[this.frames.length - 1];
    if (last && tick <= last.tick) this.frames = [];
    const index = new Map();
    frame.ids.forEach((id, i) => index.set(id, i));
    this.frames.push({
      tick,
      index,
      positions: Float64Array.from(frame.positions),  // protobufjs decodes packed floats into Arrays
      orientations: Float64Array.from(frame.orientations),
    });
    if (this.frames.length > kFramesKept) this.frames.shift();
  }

  // The newest tick held, or null.
  latestTick() {
    return this.frames.length ? this.frames[this.frames.length - 1].tick : null;
  }

  // Calls visit(id, position[3], orientation[4] as w, x, y, z) for every
  // body of the frame at `tick`, interpolated between the frames around it;
  // before the oldest frame it shows the oldest, after the newest the
  // newest (the page never guesses ahead).
  sample(tick, visit) {
    const frames = this.frames;
    if (!frames.length) return;
    let b = frames.findIndex((frame) => frame.tick > tick);
    if (b === -1) return visitFrame(frames[frames.length - 1], visit);
    if (b === 0) return visitFrame(frames[0], visit);
    const from = frames[b - 1];
    const to = frames[b];
    const alpha = (tick - from.tick) / (to.tick - from.tick);
    const position = [0, 0, 0];
    const orientation = [1, 0, 0, 0];
    for (const [id, j] of to.index) {
      const i = from.index.get(id);
      if (i === undefined) {  // spawned between the two frames
        visit(id, to.positions.subarray(3 * j, 3 * j + 3), to.orientations.subarray(4 * j, 4 * j + 4));
        continue;
      }
      for (let k = 0; k < 3; ++k) {
        position[k] = from.positions[3 * i + k] + alpha * (to.positions[3 * j + k] - from.positions[3 * i + k]);
      }
      slerp(from.orientations, 4 * i, to.orientations, 4 * j, alpha, orientation);
      visit(id, position, orientation);
    }
  }

  // Body `id`'s pose at `tick` as sample() would draw it, {position[3],
  // orientation[4] (w, x, y, z)}, or null when no frame held has the body.
  poseAt(id, tick) {
    const frames = this.frames.filter((frame) => frame.index.has(id));
    if (!frames.length) return null;
    const b = frames.findIndex((frame) => frame.tick > tick);
    const from = frames[b === -1 ? frames.length - 1 : Math.max(b - 1, 0)];
    const to = b <= 0 ? from : frames[b];
    const i = 3 * from.index.get(id), j = 3 * to.index.get(id);
    const alpha = to === from ? 0 : (tick - from.tick) / (to.tick - from.tick);
    const position = [0, 1, 2].map((k) => from.positions[i + k] + alpha * (to.positions[j + k] - from.positions[i + k]));
    const orientation = slerp(from.orientations, (4 * i) / 3, to.orientations, (4 * j) / 3, alpha, [1, 0, 0, 0]);
    return { position, orientation };
  }
}

function visitFrame(frame, visit) {
  for (const [id, i] of frame.index) {
    visit(id, frame.positions.subarray(3 * i, 3 * i + 3), frame.orientations.subarray(4 * i, 4 * i + 4));
  }
}

// Spherical interpolation from quaternion a[ia..ia+3] to b[ib..ib+3]
// (w, x, y, z) by t, along the shorter arc, into out; normalised.
export function slerp(a, ia, b, ib, t, out) {
  let bw = b[ib], bx = b[ib + 1], by = b[ib + 2], bz = b[ib + 3];
  const aw = a[ia], ax = a[ia + 1], ay = a[ia + 2], az = a[ia + 3];
  let cos = aw * bw + ax * bx + ay * by + az * bz;
  if (cos < 0) {  // q and -q are the same rotation: take the shorter way
    cos = -cos;
    bw = -bw; bx = -bx; by = -by; bz = -bz;
  }
  let wa, wb;
  if (cos > 0.9995) {  // nearly equal: linear interpolation is exact enough and stable
    wa = 1 - t;
    wb = t;
  } else {
    const angle = Math.acos(cos);
    const sin = Math.sin(angle);
    wa = Math.sin((1 - t) * angle) / sin;
    wb = Math.sin(t * angle) / sin;
  }
  out[0] = wa * aw + wb * bw;
  out[1] = wa * ax + wb * bx;
  out[2] = wa * ay + wb * by;
  out[3] = wa * az + wb * bz;
  const norm = Math.hypot(out[0], out[1], out[2], out[3]);
  for (let k = 0; k < 4; ++k) out[k] /= norm;
  return out;
}
