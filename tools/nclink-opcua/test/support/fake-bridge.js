"use strict";
// A stand-in for nclink-bridge that speaks exactly the contract nclink-opcua
// reads (docs/opcua.md "The bridge contract"), driven by the test:
//   GET  /nclink/v1/devices
//   GET  /nclink/v1/devices/{dev}/nodeset.xml?profile=...
//   GET  /nclink/v1/devices/{dev}/model   (404 when the test gave none)
//   GET  /nclink/v1/devices/{dev}/history (every value the test gave, as the bridge's buffer)
//   POST /nclink/v1/devices/{dev}/set
//   POST /nclink/v1/devices/{dev}/call
//   GET  /nclink/v1/stream  (snapshot per device, then value/device events, ": ping")
const http = require("node:http");

/// A request's body as JSON; undefined when it is not JSON.
async function readJson(req) {
  const chunks = [];
  for await (const c of req) chunks.push(c);
  try {
    return JSON.parse(Buffer.concat(chunks).toString("utf8"));
  } catch {
    return undefined;
  }
}

class FakeBridge {
  constructor({ pingMs = 1000 } = {}) {
    this.devices = new Map(); // dev -> {dev, name, state, version, nodeset, values: Map id -> {id,value,time,quality}}
    this.clients = new Set();
    this.sets = []; // every set request: {dev, id, value}
    this.setAnswer = () => ({ code: "OK" }); // (dev, id, value) -> answer object (or a Promise)
    this.nodesetRequests = [];
    this.calls = []; // every call request: {dev, method, args, timeoutMs}
    this.callAnswer = () => ({ code: "OK", result: "finished" }); // (dev, method, args) -> answer (or a Promise)
    this.pingMs = pingMs;
    this.server = null;
    this.port = 0;
  }

  addDevice({ dev, name = dev, state = "online", version = "1", nodeset, values = {}, model = null }) {
    const d = { dev, name, state, version, nodeset, values: new Map(), model, history: [] };
    for (const [id, value] of Object.entries(values)) {
      d.values.set(id, { id, value, time: Date.now(), quality: "good" });
      d.history.push(d.values.get(id));
    }
    this.devices.set(dev, d);
    return d;
  }

  get url() {
    return `http://127.0.0.1:${this.port}`;
  }

  async start(port = 0) {
    this.server = http.createServer((req, res) => this.handle(req, res));
    this.server.keepAliveTimeout = 1000;
    await new Promise((resolve, reject) => {
      this.server.once("error", reject);
      this.server.listen(port, "127.0.0.1", resolve);
    });
    this.port = this.server.address().port;
    this.pinger = setInterval(() => this.broadcastRaw(": ping\n\n"), this.pingMs);
  }

  /// Gone: every connection cut, nothing listening (the port stays known so
  /// start(this.port) brings the same bridge back).
  async stop() {
    clearInterval(this.pinger);
    for (const c of this.clients) c.destroy();
    this.clients.clear();
    if (!this.server) return;
    const server = this.server;
    this.server = null;
    server.closeAllConnections();
    await new Promise((resolve) => server.close(resolve));
  }

  /// The stream drops (the bridge stays up).
  dropStreams() {
    for (const c of this.clients) c.destroy();
    this.clients.clear();
  }

  broadcastRaw(text) {
    for (const c of this.clients) c.write(text);
  }

  send(type, data) {
    this.broadcastRaw(`event: ${type}\ndata: ${JSON.stringify(data)}\n\n`);
  }

  /// A value from the machine: cached for later snapshots, sent now.
  pushValue(dev, id, value, { quality = "good", time = Date.now() } = {}) {
    const v = { id, value, time, quality };
    this.devices.get(dev).values.set(id, v);
    this.devices.get(dev).history.push(v);
    this.send("value", { dev, ...v });
    return v;
  }

  setState(dev, state) {
    const d = this.devices.get(dev);
    d.state = state;
    this.send("device", { dev, state, version: d.version });
  }

  /// The model changed: new nodeset, new version, announced on the stream.
  changeModel(dev, nodeset, version) {
    const d = this.devices.get(dev);
    d.nodeset = nodeset;
    d.version = version;
    this.send("device", { dev, state: d.state, version });
  }

  snapshotOf(d) {
    return { dev: d.dev, state: d.state, values: [...d.values.values()] };
  }

  async handle(req, res) {
    const url = new URL(req.url, "http://x");
    const json = (status, body) => {
      res.writeHead(status, { "Content-Type": "application/json" });
      res.end(JSON.stringify(body));
    };
    if (req.method === "GET" && url.pathname === "/nclink/v1/devices") {
      return json(200, { devices: [...this.devices.values()].map((d) => ({ dev: d.dev, name: d.name, state: d.state, version: d.version })) });
    }
    if (req.method === "GET" && url.pathname === "/nclink/v1/stream") {
      res.writeHead(200, { "Content-Type": "text/event-stream", "Cache-Control": "no-cache" });
      res.flushHeaders();
      for (const d of this.devices.values()) res.write(`event: snapshot\ndata: ${JSON.stringify(this.snapshotOf(d))}\n\n`);
      this.clients.add(res);
      res.on("close", () => this.clients.delete(res));
      return undefined;
    }
    const m = /^\/nclink\/v1\/devices\/([^/]+)\/(nodeset\.xml|set|model|call|history)$/.exec(url.pathname);
    const d = m && this.devices.get(decodeURIComponent(m[1]));
    if (!d) return json(404, { code: "NG", error: 202, reason: "Unavailable" });
    if (req.method === "GET" && m[2] === "nodeset.xml") {
      this.nodesetRequests.push({ dev: d.dev, profile: url.searchParams.get("profile") });
      // As the bridge: no nodeset until the device's model is known.
      if (!d.nodeset) return json(404, { error: `the model of ${d.dev} is not known yet` });
      res.writeHead(200, { "Content-Type": "application/xml" });
      return res.end(d.nodeset);
    }
    if (req.method === "GET" && m[2] === "history") {
      this.historyRequests = (this.historyRequests || []).concat([Object.fromEntries(url.searchParams)]);
      const id = url.searchParams.get("id");
      const from = url.searchParams.has("from") ? Number(url.searchParams.get("from")) : -Infinity;
      const to = url.searchParams.has("to") ? Number(url.searchParams.get("to")) : Infinity;
      const max = url.searchParams.has("max") ? Number(url.searchParams.get("max")) : 10000;
      const all = d.history.filter((v) => v.id === id && v.time >= from && v.time <= to);
      return json(200, { dev: d.dev, id, values: all.slice(0, max).map(({ value, time, quality }) => ({ value, time, quality })), more: all.length > max });
    }
    if (req.method === "GET" && m[2] === "model") {
      if (!d.model) return json(404, { error: `the model of ${d.dev} is not known yet` });
      return json(200, d.model);
    }
    if (req.method === "POST" && m[2] === "call") {
      const body = await readJson(req);
      if (body === undefined) return json(400, { code: "NG", error: 412, reason: "syntax error" });
      this.calls.push({ dev: d.dev, method: body.method, args: body.args, timeoutMs: body.timeout_ms });
      const answer = await this.callAnswer(d.dev, body.method, body.args);
      return json(answer.code === "OK" ? 200 : answer.status || 200, answer);
    }
    if (req.method === "POST" && m[2] === "set") {
      const body = await readJson(req);
      if (body === undefined) return json(400, { code: "NG", error: 412, reason: "syntax error" });
      this.sets.push({ dev: d.dev, id: body.id, value: body.value });
      const answer = await this.setAnswer(d.dev, body.id, body.value);
      return json(answer.code === "OK" ? 200 : 400, answer);
    }
    return json(404, { code: "NG", error: 202, reason: "Unavailable" });
  }
}

module.exports = { FakeBridge };
