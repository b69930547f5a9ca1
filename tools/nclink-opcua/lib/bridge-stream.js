"use strict";
// The bridge's live stream (GET /nclink/v1/stream, Server-Sent Events), kept
// open for as long as the server runs: when it drops, cannot be opened or goes
// silent longer than the idle limit, it is opened again after a backoff
// (250 ms doubling up to the maximum; back to 250 ms once a stream opened).
//
// Events (all on the event loop thread):
//   "open"            the stream answered 200; a snapshot per device follows
//   "event" {type, data}   one SSE event; data parsed from JSON
//   "malformed" {type, text, reason}   an event whose data is not JSON
//   "down" reason     the stream is gone (emitted once per open or failed attempt)
const { EventEmitter } = require("node:events");
const { SseParser } = require("./sse");
const { transportOf } = require("./bridge-client");

const INITIAL_DELAY_MS = 250;

/// Wait before reconnect attempt `attempt` (0 = the first after a drop).
function backoffDelay(attempt, maxMs, initialMs = INITIAL_DELAY_MS) {
  const d = initialMs * 2 ** Math.min(attempt, 30);
  return Math.min(d, maxMs);
}

class BridgeStream extends EventEmitter {
  constructor(base, { reconnectMaxMs = 10000, idleMs = 45000 } = {}) {
    super();
    this.url = new URL(base + "/nclink/v1/stream");
    this.reconnectMaxMs = reconnectMaxMs;
    this.idleMs = idleMs;
    this.attempt = 0;
    this.stopped = true;
    this.req = null;
    this.retryTimer = null;
    this.idleTimer = null;
  }

  start() {
    this.stopped = false;
    this.connect();
  }

  stop() {
    this.stopped = true;
    clearTimeout(this.retryTimer);
    clearTimeout(this.idleTimer);
    if (this.req) this.req.destroy();
    this.req = null;
  }

  connect() {
    if (this.stopped) return;
    let ended = false;
    const parser = new SseParser();
    const end = (reason) => {
      if (ended) return;
      ended = true;
      clearTimeout(this.idleTimer);
      if (this.req === req) this.req = null;
      req.destroy();
      if (this.stopped) return;
      this.emit("down", reason);
      const delay = backoffDelay(this.attempt++, this.reconnectMaxMs);
      this.retryTimer = setTimeout(() => this.connect(), delay);
    };
    const touch = () => {
      clearTimeout(this.idleTimer);
      this.idleTimer = setTimeout(() => end(`no data for ${this.idleMs} ms`), this.idleMs);
    };
    const req = transportOf(this.url).get(this.url, { headers: { Accept: "text/event-stream", "Cache-Control": "no-cache" } }, (res) => {
      if (res.statusCode !== 200) {
        res.resume();
        end(`HTTP ${res.statusCode}`);
        return;
      }
      this.attempt = 0;
      touch();
      this.emit("open");
      res.setEncoding("utf8");
      res.on("data", (chunk) => {
        touch();
        for (const e of parser.push(chunk)) {
          if (e.comment !== undefined) continue;
          let data;
          try {
            data = JSON.parse(e.data);
          } catch (err) {
            this.emit("malformed", { type: e.type, text: e.data, reason: err.message });
            continue;
          }
          this.emit("event", { type: e.type, data });
        }
      });
      res.on("end", () => end("the bridge closed the stream"));
      res.on("error", (err) => end(err.message));
    });
    this.req = req;
    touch();
    req.on("error", (err) => end(err.code || err.message));
  }
}

module.exports = { BridgeStream, backoffDelay };
