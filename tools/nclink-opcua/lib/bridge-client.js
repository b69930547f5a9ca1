"use strict";
// The nclink-bridge JSON API (docs/opcua.md, "The bridge contract"):
//   GET  /nclink/v1/devices
//   GET  /nclink/v1/devices/{dev}/nodeset.xml?profile=basic|cnc
//   GET  /nclink/v1/devices/{dev}/model
//   GET  /nclink/v1/devices/{dev}/history?id=&from=&to=&max=
//   POST /nclink/v1/devices/{dev}/set   {"id", "value"}
//   POST /nclink/v1/devices/{dev}/call  {"method", "args", "timeout_ms"}
//   GET  /nclink/v1/stream              (lib/bridge-stream.js)
const http = require("node:http");
const https = require("node:https");

/// kind: "unreachable" (no connection), "timeout", "http" (unexpected status),
/// "malformed" (an answer that does not follow the contract).
class BridgeError extends Error {
  constructor(kind, message, status) {
    super(message);
    this.kind = kind;
    this.status = status;
  }
}

function transportOf(url) {
  return url.protocol === "https:" ? https : http;
}

/// The NC-Link answer of a POST (Set, Method/Call): {code: "OK", ...} or
/// {code: "NG", error, reason}, with any HTTP status; anything else is a
/// BridgeError.
function okOrNg(path, r) {
  let answer;
  try {
    answer = JSON.parse(r.body);
  } catch {
    throw new BridgeError(r.status === 200 ? "malformed" : "http", `POST ${path}: HTTP ${r.status}, not a JSON answer`, r.status);
  }
  if (answer && (answer.code === "OK" || answer.code === "NG")) return answer;
  throw new BridgeError(r.status === 200 ? "malformed" : "http", `POST ${path}: HTTP ${r.status}, no "code" OK/NG`, r.status);
}

class BridgeClient {
  /// base: bridge URL without trailing slash (options.parseBridgeUrl).
  constructor(base, { timeoutMs = 10000, callTimeoutMs = 60000 } = {}) {
    this.base = base;
    this.timeoutMs = timeoutMs;
    this.callTimeoutMs = callTimeoutMs;
    // One keep-alive agent: a write per OPC UA Write should not pay a TCP handshake.
    this.agent = new (transportOf(new URL(base)).Agent)({ keepAlive: true, maxSockets: 8 });
  }

  url(path) {
    return new URL(this.base + path);
  }

  devicePath(dev, tail) {
    return `/nclink/v1/devices/${encodeURIComponent(dev)}/${tail}`;
  }

  /// -> {status, body (string)}; rejects with BridgeError unreachable/timeout.
  request(method, path, body, timeoutMs = this.timeoutMs) {
    const url = this.url(path);
    return new Promise((resolve, reject) => {
      const headers = { Accept: method === "GET" && path.endsWith(".xml") ? "application/xml" : "application/json" };
      let payload;
      if (body !== undefined) {
        payload = Buffer.from(JSON.stringify(body), "utf8");
        headers["Content-Type"] = "application/json";
        headers["Content-Length"] = String(payload.length);
      }
      const req = transportOf(url).request(url, { method, headers, agent: this.agent }, (res) => {
        const chunks = [];
        res.on("data", (c) => chunks.push(c));
        res.on("end", () => resolve({ status: res.statusCode, body: Buffer.concat(chunks).toString("utf8") }));
        res.on("error", (e) => reject(new BridgeError("unreachable", `${method} ${url.pathname}: ${e.message}`)));
      });
      req.setTimeout(timeoutMs, () => {
        req.destroy(new BridgeError("timeout", `${method} ${url.pathname}: no answer in ${timeoutMs} ms`));
      });
      req.on("error", (e) => {
        reject(e instanceof BridgeError ? e : new BridgeError("unreachable", `${method} ${url.pathname}: ${e.code || e.message}`));
      });
      req.end(payload);
    });
  }

  async getJson(path) {
    const r = await this.request("GET", path);
    if (r.status !== 200) throw new BridgeError("http", `GET ${path}: HTTP ${r.status}`, r.status);
    try {
      return JSON.parse(r.body);
    } catch {
      throw new BridgeError("malformed", `GET ${path}: the answer is not JSON`);
    }
  }

  /// -> [{dev, name, state, version}]
  async devices() {
    const answer = await this.getJson("/nclink/v1/devices");
    if (!answer || !Array.isArray(answer.devices))
      throw new BridgeError("malformed", "GET /nclink/v1/devices: no \"devices\" array");
    return answer.devices.filter((d) => d && typeof d.dev === "string" && d.dev !== "");
  }

  /// -> the NodeSet2 XML text of one device.
  async nodeset(dev, profile) {
    const path = this.devicePath(dev, `nodeset.xml?profile=${encodeURIComponent(profile)}`);
    const r = await this.request("GET", path);
    if (r.status !== 200) throw new BridgeError("http", `GET ${path}: HTTP ${r.status}`, r.status);
    if (!r.body.includes("<UANodeSet")) throw new BridgeError("malformed", `GET ${path}: not a NodeSet2 document`);
    return r.body;
  }

  /// An NC-Link Set of one item -> {code: "OK"} or {code: "NG", error, reason}.
  /// An NG answer may come with any HTTP status; anything else is a BridgeError.
  async set(dev, id, value) {
    const path = this.devicePath(dev, "set");
    const r = await this.request("POST", path, { id, value });
    return okOrNg(path, r);
  }

  /// The device's NC-Link model (the adapter's Probe answer).
  async model(dev) {
    return this.getJson(this.devicePath(dev, "model"));
  }

  /// The item's values the bridge still buffers, from..to (ms, both ends
  /// included; undefined = open), oldest first, at most max ->
  /// {values: [{value, time, quality}], more}.
  async history(dev, id, from, to, max) {
    const query = new URLSearchParams({ id });
    if (from !== undefined) query.set("from", String(Math.floor(from)));
    if (to !== undefined) query.set("to", String(Math.ceil(to)));
    if (max !== undefined) query.set("max", String(max));
    const answer = await this.getJson(this.devicePath(dev, `history?${query}`));
    if (!answer || !Array.isArray(answer.values)) throw new BridgeError("malformed", `GET history of ${dev}/${id}: no "values" array`);
    return answer;
  }

  /// An NC-Link Method/Call, answered at its Method/Result:
  /// {code: "OK", result, return} or {code: "NG", result, error, reason}. The
  /// bridge waits callTimeoutMs for the result (then answers NG 203); the
  /// HTTP request a little longer, so the bridge's answer wins.
  async call(dev, method, args) {
    const path = this.devicePath(dev, "call");
    const r = await this.request("POST", path, { method, args, timeout_ms: this.callTimeoutMs }, this.callTimeoutMs + 5000);
    return okOrNg(path, r);
  }

  close() {
    this.agent.destroy();
  }
}

module.exports = { BridgeClient, BridgeError, transportOf };
