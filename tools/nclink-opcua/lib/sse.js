"use strict";
// Server-Sent Events parser (WHATWG HTML "event stream interpretation"): text
// chunks in, complete events out. Lines end in CRLF, LF or CR; a blank line
// dispatches; "data" lines join with LF; lines starting with ':' are comments
// (the bridge's ": ping" heartbeats). Chunks may split lines anywhere.

class SseParser {
  constructor() {
    this.buffer = "";
    this.pendingCR = false;
    this.reset();
  }

  reset() {
    this.type = "";
    this.data = [];
    this.id = undefined;
  }

  /// Feeds a chunk; returns the events it completed: {type, data, id} with
  /// type "message" when the event had no "event:" field, or {comment}.
  push(chunk) {
    const out = [];
    let text = chunk;
    // A CR ending the previous chunk may be the first half of a CRLF.
    if (this.pendingCR && text.startsWith("\n")) text = text.slice(1);
    this.pendingCR = false;
    this.buffer += text;
    let start = 0;
    for (let i = 0; i < this.buffer.length; i++) {
      const c = this.buffer[i];
      if (c !== "\n" && c !== "\r") continue;
      const line = this.buffer.slice(start, i);
      if (c === "\r") {
        if (i + 1 < this.buffer.length) {
          if (this.buffer[i + 1] === "\n") i++;
        } else {
          this.pendingCR = true;
        }
      }
      start = i + 1;
      this.line(line, out);
    }
    this.buffer = this.buffer.slice(start);
    return out;
  }

  line(line, out) {
    if (line === "") {
      if (this.data.length > 0)
        out.push({ type: this.type || "message", data: this.data.join("\n"), id: this.id });
      this.reset();
      return;
    }
    if (line.startsWith(":")) {
      out.push({ comment: line.slice(1).trimStart() });
      return;
    }
    const colon = line.indexOf(":");
    const field = colon < 0 ? line : line.slice(0, colon);
    let value = colon < 0 ? "" : line.slice(colon + 1);
    if (value.startsWith(" ")) value = value.slice(1);
    if (field === "event") this.type = value;
    else if (field === "data") this.data.push(value);
    else if (field === "id") this.id = value;
    // "retry" and unknown fields: ignored (the reconnect policy is our own).
  }
}

module.exports = { SseParser };
