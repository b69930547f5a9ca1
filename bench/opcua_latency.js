"use strict";
// nclink-opcua latency against the fake bridge (not a test; figures for
// docs/opcua.md). Starts the fake bridge in this process, nclink-opcua as a
// child process (as deployed), and a node-opcua client here, so every
// timestamp below comes from this process's monotonic clock.
//
//   node bench/opcua_latency.js [--reads N] [--values N] [--rate HZ]
//
// 1. Read latency: one Read of one item's Value, N times, against a Read of a
//    namespace-0 variable of the same server (Server_ServerStatus_State):
//    the floor is what node-opcua costs for any Read on this machine.
// 2. Stream -> data change: the fake bridge sends `event: value` for three
//    items at HZ; the delay until the client's monitored item reports it
//    (publishing interval 10 ms asked, node-opcua revises it to its 50 ms
//    minimum; sampling interval 0 asked; n = the changes reported), against the floor of the same SSE event reaching a
//    plain HTTP reader in this process. An item whose
//    MinimumSamplingInterval is 0 is delivered on change; any other is
//    sampled at its MinimumSamplingInterval in the values' own time
//    (docs/opcua.md "Subscriptions and sampling"): the mapping writes 1 ms
//    for positions and 100 ms for most items, so one item of each kind is
//    measured. For the whole path from a Sample DTU see
//    bench/opcua_e2e_latency.js.
const path = require("node:path");
const http = require("node:http");
const { performance } = require("node:perf_hooks");

const dir = path.join(__dirname, "..", "tools", "nclink-opcua");
const opcua = require(path.join(dir, "lib", "node-opcua"));
const { FakeBridge } = require(path.join(dir, "test", "support", "fake-bridge"));
const { makeNodeset, testDevice } = require(path.join(dir, "test", "support", "fake-nodeset"));
const { freePort, startServer, connect, tempDir } = require(path.join(dir, "test", "support", "harness"));
const { SseParser } = require(path.join(dir, "lib", "sse"));

const { AttributeIds } = opcua;
opcua.debug.setWarningLogger(() => {});

function arg(name, fallback) {
  const i = process.argv.indexOf(name);
  return i > 0 ? Number(process.argv[i + 1]) : fallback;
}
const READS = arg("--reads", 2000);
const VALUES = arg("--values", 500);
const RATE = arg("--rate", 50);

function percentiles(samples) {
  const s = [...samples].sort((a, b) => a - b);
  const at = (p) => s[Math.min(s.length - 1, Math.floor((p / 100) * s.length))];
  return { p50: at(50), p99: at(99), n: s.length };
}
const ms = (x) => `${x.toFixed(3)} ms`;

/// Reads of `nodeIds`, interleaved so that load and JIT warm-up hit each alike.
async function readLatencies(session, nodeIds) {
  const samples = nodeIds.map(() => []);
  for (let i = 0; i < 50; i++) for (const nodeId of nodeIds) await session.read({ nodeId, attributeId: AttributeIds.Value }); // warm-up
  for (let i = 0; i < READS; i++) {
    for (let k = 0; k < nodeIds.length; k++) {
      const t = performance.now();
      await session.read({ nodeId: nodeIds[k], attributeId: AttributeIds.Value });
      samples[k].push(performance.now() - t);
    }
  }
  return samples.map(percentiles);
}

/// A plain SSE reader of the bridge stream: the floor of delivery.
function sseReader(url, onValue) {
  const parser = new SseParser();
  const req = http.get(`${url}/nclink/v1/stream`, (res) => {
    res.setEncoding("utf8");
    res.on("data", (chunk) => {
      const now = performance.now();
      for (const e of parser.push(chunk)) if (e.type === "value") onValue(JSON.parse(e.data), now);
    });
  });
  return () => req.destroy();
}

async function main() {
  const device = testDevice("bench-mill", {
    extraItems: [
      { id: "feed_speed", dataType: "Double", msi: 100, type: "FEED_SPEED" }, // most items, as the mapping writes them
      { id: "x_speed", dataType: "Double", msi: 0, type: "SPEED" }, // exception-based
    ],
  });
  device.components[0].items[0].msi = 1; // x_position as the mapping writes positions
  const bridge = new FakeBridge({ pingMs: 10000 });
  bridge.addDevice({ dev: "bench-mill", nodeset: makeNodeset(device), values: { x_position: 0, feed_speed: 0, x_speed: 0, tool_number: 1 } });
  await bridge.start();
  const port = await freePort();
  const pki = tempDir("nclink-opcua-bench-pki-");
  const server = startServer(["--bridge", bridge.url, "--port", String(port), "--pki", pki]);
  await server.waitForLine(/serving \d+ items/);
  const c = await connect(opcua, `opc.tcp://127.0.0.1:${port}`);
  const ns = (await c.session.readNamespaceArray()).indexOf("urn:nclink:device:bench-mill");

  const [floorRead, itemRead, writableRead] = await readLatencies(c.session, ["i=2259", `ns=${ns};s=tool_number`, `ns=${ns};s=spindle_override`]);

  const subscription = await c.session.createSubscription2({ requestedPublishingInterval: 10, publishingEnabled: true, requestedMaxKeepAliveCount: 100, requestedLifetimeCount: 1000, maxNotificationsPerPublish: 0 });
  const sent = new Map(); // "id:value" -> send time
  const ITEMS = ["x_speed", "x_position", "feed_speed"];
  const delays = { sse: [], x_speed: [], x_position: [], feed_speed: [] };
  const revised = {};
  for (const id of ITEMS) {
    const item = await subscription.monitor({ nodeId: `ns=${ns};s=${id}`, attributeId: AttributeIds.Value }, { samplingInterval: 0, queueSize: 1000, discardOldest: true }, 0);
    revised[id] = item.statistics ? item.statistics.revisedSamplingInterval : item.monitoringParameters.samplingInterval;
    item.on("changed", (dv) => {
      const t = sent.get(`${id}:${dv.value.value}`);
      if (t !== undefined) delays[id].push(performance.now() - t);
    });
  }
  const stopReader = sseReader(bridge.url, (v, now) => {
    const t = sent.get(`${v.id}:${v.value}`);
    if (t !== undefined && v.id === "x_speed") delays.sse.push(now - t);
  });
  await new Promise((r) => setTimeout(r, 1000));

  for (let i = 1; i <= VALUES; i++) {
    for (const id of ITEMS) {
      const value = i + 0.5;
      sent.set(`${id}:${value}`, performance.now());
      bridge.pushValue("bench-mill", id, value);
    }
    await new Promise((r) => setTimeout(r, 1000 / RATE));
  }
  await new Promise((r) => setTimeout(r, 1500));
  stopReader();

  const report = (label, p, floor) => `${label.padEnd(66)} p50 ${ms(p.p50)}  p99 ${ms(p.p99)}  (n=${p.n})${floor ? `  p50 ratio to floor ${(p.p50 / floor.p50).toFixed(2)}` : ""}`;
  console.log(`nclink-opcua latency, node ${process.version}, ${READS} reads, ${VALUES} values at ${RATE} Hz, publishing interval ${subscription.publishingInterval} ms (10 asked)`);
  console.log(report("Read floor: ns=0 ServerStatus.State", floorRead));
  console.log(report("Read of an item (tool_number)", itemRead, floorRead));
  console.log(report("Read of a writable item (spindle_override)", writableRead, floorRead));
  const sse = percentiles(delays.sse);
  console.log(report("stream floor: SSE event to a plain reader", sse));
  console.log(report(`stream -> notification, MinimumSamplingInterval 0 (revised ${revised.x_speed})`, percentiles(delays.x_speed), sse));
  console.log(report(`stream -> notification, MinimumSamplingInterval 1 (revised ${revised.x_position})`, percentiles(delays.x_position), sse));
  console.log(report(`stream -> notification, MinimumSamplingInterval 100 (revised ${revised.feed_speed})`, percentiles(delays.feed_speed), sse));

  await subscription.terminate();
  await c.close();
  await server.stop();
  await bridge.stop();
  require("node:fs").rmSync(pki, { recursive: true, force: true });
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
