// Which frames of a pose stream read over NATS may be shown.
//
// A stream's frames carry a sequence number (1, 2, 3, ... from when the
// server began publishing). A DELTA change holds only what moved since frame
// `sequence - 1`, so it is right only on top of exactly that frame; a reader
// that missed one (it joined late, or NATS dropped messages of a slow
// consumer) shows nothing new until a whole frame: the next key frame
// published, or the reply to a request on the stream's `.key` subject (the
// stream's latest frame as a key frame, with that frame's sequence). FULL,
// QUANTIZED and DELTA key frames are whole and always right.
//
// The gate sees every frame in the order it reaches the page, published
// ones and key replies mixed (they come on different subjects, so a key
// reply may overtake frames published before it). It lets a frame through
// when it is whole and not older than what was shown, or when it is the
// change that follows what was shown, and says when to ask for a key frame.

// The PoseEncoding number of DELTA.
const kDelta = 2;

// A frame that stands alone: every body of the stream.
const isWhole = (frame) => frame.encoding !== kDelta || frame.keyFrame;

export class SequenceGate {
  constructor() {
    this.held = 0;          // the sequence of the state shown; 0: none to build on
    this.keyShown = 0;      // a key reply shown, until a published frame passes it
    this.keyRequested = false;  // a key frame was asked for and has not come
  }

  // A frame published on the stream's subject; returns {show, requestKey}:
  // show it (it is right on top of what was shown), and ask for a key frame
  // now (out of step, and none was asked for).
  published(frame) {
    const sequence = Number(frame.sequence);
    if (this.keyShown !== 0) {
      // Frames published before the key reply that was shown may still
      // come: they are older than what is on screen. A restarted server
      // begins again at 1, which ends the wait as a newer frame does.
      if (sequence <= this.keyShown && sequence !== 1) return { show: false, requestKey: false };
      this.keyShown = 0;
    }
    if (isWhole(frame)) return this.takeWhole(sequence);
    if (this.held !== 0 && sequence === this.held + 1) {
      this.held = sequence;
      return { show: true, requestKey: false };
    }
    // A change already contained in what is shown: nothing new, in step.
    if (this.held !== 0 && sequence <= this.held) return { show: false, requestKey: false };
    // A change on top of a frame this page never had.
    this.held = 0;
    if (this.keyRequested) return { show: false, requestKey: false };
    this.keyRequested = true;
    return { show: false, requestKey: true };
  }

  // The reply to a request on the stream's `.key` subject.
  keyReply(frame) {
    const sequence = Number(frame.sequence);
    this.keyRequested = false;
    if (!isWhole(frame)) return { show: false, requestKey: false };  // a change restores nothing
    // Out of step, any whole frame restores; in step, only a newer one is news.
    if (this.held !== 0 && sequence <= this.held) return { show: false, requestKey: false };
    this.keyShown = sequence;
    return this.takeWhole(sequence);
  }

  // A key frame request failed or went unanswered: the next frame out of
  // step may ask again.
  keyRequestFailed() {
    this.keyRequested = false;
  }

  takeWhole(sequence) {
    this.held = sequence;
    this.keyRequested = false;
    return { show: true, requestKey: false };
  }
}
