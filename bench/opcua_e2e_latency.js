"use strict";
// NC-Link Sample DTU -> OPC UA DataChange, end to end (not a test; figures
// for docs/opcua.md "Performance"): a real mosquitto on a free loopback
// port, the simulated mill (nclink-sim: ch_fast samples x_position every
// 1 ms and uploads a Sample DTU of 100 rows every 100 ms), nclink-bridge,
// nclink-opcua, and a node-opcua client in this process monitoring
// x_position with the channel's own sampling interval (1 ms).
//
//   node bench/opcua_e2e_latency.js [--seconds N] [--bin DIR] [--sampling MS]
//
// DIR holds nclink-sim and nclink-bridge (default build/bin). Every time is
// this machine's wall clock in ms (the sim stamps rows with the same clock):
// - floor: the Sample DTU reaching a plain MQTT subscriber (mosquitto_sub,
//   which stamps each message as it reads it, %U), minus the time of the
//   DTU's last row (its sample time; the DTU cannot leave before it);
// - DataChange: the client's notification of the value whose
//   SourceTimestamp is that last row's time, minus the same row time;
// - added: DataChange minus floor, per DTU (what bridge + nclink-opcua +
//   OPC UA publishing add to MQTT delivery).
// Between the two, the same row as the bridge's stream event at a plain HTTP
// reader in this process shows which part is the bridge's.
// The first row of a DTU waits the upload period (100 ms) at the machine
// whatever the consumer; the last row is the one that shows the consumer's
// delay. A DTU whose last row brought no change (the position held still)
// has no DataChange and is left out (n says how many counted).
const path = require("node:path");
const fs = require("node:fs");
const net = require("node:net");
const { spawn } = require("node:child_process");
const { performance } = require("node:perf_hooks");

const root = path.join(__dirname, "..");
const dir = path.join(root, "tools", "nclink-opcua");
const opcua = require(path.join(dir, "lib", "node-opcua"));
const { freePort, startServer, connect, tempDir, waitUntil, spawnLogged: run, stopProcess } = require(path.join(dir, "test", "support", "harness"));
const { SseParser } = require(path.join(dir, "lib", "sse"));

const { AttributeIds, DataType } = opcua;
opcua.debug.setWarningLogger(() => {});

function arg(name, fallback) {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : fallback;
}
const SECONDS = Number(arg("--seconds", 30));
const BIN = path.resolve(arg("--bin", path.join(root, "build", "bin")));
const SAMPLING = Number(arg("--sampling", 1));
const DEV = "nclink-sim-mill-01";
const CHANNEL = "ch_fast";
const ITEM = "x_position";

const now = () => performance.timeOrigin + performance.now(); // wall clock, sub-ms

function percentiles(samples) {
  const s = [...samples].sort((a, b) => a - b);
  const at = (p) => s[Math.min(s.length - 1, Math.floor((p / 100) * s.length))];
  return { p50: at(50), p99: at(99), n: s.length };
}

const listening = (port) =>
  new Promise((resolve) => {
    const s = net.connect(port, "127.0.0.1", () => (s.end(), resolve(true)));
    s.on("error", () => resolve(false));
  });

/// mosquitto_sub on the channel's topic -> [{arrival, lastRow}] (arrival as
/// mosquitto_sub stamped it).
function mqttFloor(port, topic, dtus) {
  const proc = spawn("mosquitto_sub", ["-h", "127.0.0.1", "-p", String(port), "-q", "1", "-t", topic, "-F", "%U %p"], { stdio: ["ignore", "pipe", "inherit"] });
  let buffer = "";
  proc.stdout.setEncoding("utf8").on("data", (chunk) => {
    buffer += chunk;
    let nl;
    while ((nl = buffer.indexOf("\n")) >= 0) {
      const line = buffer.slice(0, nl);
      buffer = buffer.slice(nl + 1);
      const sp = line.indexOf(" ");
      try {
        const dtu = JSON.parse(line.slice(sp + 1));
        const rows = Math.max(...dtu.data.map((d) => (Array.isArray(d.data) ? d.data.length : 0)));
        dtus.push({ arrival: Number(line.slice(0, sp)) * 1000, lastRow: Number(dtu.beginTime) + (rows - 1) * 1 });
      } catch {
        // not a DTU of this channel: ignored
      }
    }
  });
  return proc;
}

/// A plain reader of the bridge's stream: source time of each ITEM value -> arrival.
function sseReader(url, seen) {
  const parser = new SseParser();
  const req = require("node:http").get(`${url}/nclink/v1/stream`, (res) => {
    res.setEncoding("utf8");
    res.on("data", (chunk) => {
      const t = now();
      for (const e of parser.push(chunk)) {
        if (e.type !== "value") continue;
        const v = JSON.parse(e.data);
        if (v.id === ITEM && v.dev === DEV) seen.set(Number(new Date(v.time)), t);
      }
    });
  });
  return () => req.destroy();
}

async function main() {
  for (const name of ["nclink-sim", "nclink-bridge"])
    if (!fs.existsSync(path.join(BIN, name))) throw new Error(`${path.join(BIN, name)} not found (build it, or --bin DIR)`);
  const work = tempDir("nclink-opcua-e2e-bench-");
  const procs = [];
  try {
    const brokerPort = await freePort();
    const broker = `tcp://127.0.0.1:${brokerPort}`;
    const conf = fs.readFileSync(path.join(root, "tools", "mosquitto", "nclink.conf"), "utf8");
    fs.writeFileSync(path.join(work, "mosquitto.conf"), `listener ${brokerPort} 127.0.0.1\nallow_anonymous true\npersistence false\n${conf}`);
    procs.push(run(fs.existsSync("/usr/sbin/mosquitto") ? "/usr/sbin/mosquitto" : "mosquitto", ["-c", path.join(work, "mosquitto.conf")], work));
    await waitUntil(() => listening(brokerPort), { what: "mosquitto" });
    procs.push(run(path.join(BIN, "nclink-sim"), ["--broker", broker, "--persistence", path.join(work, "sim-state")], work));
    const httpPort = await freePort();
    const bridgeUrl = `http://127.0.0.1:${httpPort}`;
    procs.push(run(path.join(BIN, "nclink-bridge"), ["--broker", broker, "--http", `127.0.0.1:${httpPort}`, "--shdr", "off", "--device", DEV], work));
    await waitUntil(async () => {
      const res = await fetch(`${bridgeUrl}/nclink/v1/devices/${DEV}/nodeset.xml?profile=basic`);
      return res.ok;
    }, { ms: 60000, what: "the bridge's nodeset of the mill" });
    const port = await freePort();
    const server = startServer(["--bridge", bridgeUrl, "--port", String(port), "--pki", path.join(work, "pki")]);
    procs.push(server.proc);
    await server.waitForLine(/device nclink-sim-mill-01: serving \d+ items/, { ms: 120000 });
    const c = await connect(opcua, `opc.tcp://127.0.0.1:${port}`);
    const ns = (await c.session.readNamespaceArray()).indexOf(`urn:nclink:device:${DEV}`);
    // The mill moves as long as its feed override is not 0; make sure it does.
    await c.session.write({ nodeId: `ns=${ns};s=feed_override`, attributeId: AttributeIds.Value, value: { value: { dataType: DataType.Double, value: 100 } } });

    const changes = new Map(); // source time (ms) -> arrival
    const subscription = await c.session.createSubscription2({ requestedPublishingInterval: 10, publishingEnabled: true, requestedMaxKeepAliveCount: 100, requestedLifetimeCount: 1000, maxNotificationsPerPublish: 0 });
    const item = await subscription.monitor({ nodeId: `ns=${ns};s=${ITEM}`, attributeId: AttributeIds.Value }, { samplingInterval: SAMPLING, queueSize: 5000, discardOldest: true }, opcua.TimestampsToReturn ? opcua.TimestampsToReturn.Both : 2);
    item.on("changed", (dv) => {
      const t = now();
      if (dv.sourceTimestamp) changes.set(dv.sourceTimestamp.getTime(), t);
    });
    const streamed = new Map(); // source time (ms) -> arrival at a plain SSE reader
    const stopReader = sseReader(bridgeUrl, streamed);
    const dtus = [];
    const sub = mqttFloor(brokerPort, `Sample/${DEV}/${CHANNEL}`, dtus);
    procs.push(sub);
    await new Promise((r) => setTimeout(r, 2000)); // past the first DTUs and the initial value
    const from = dtus.length;
    await new Promise((r) => setTimeout(r, SECONDS * 1000));
    await new Promise((r) => setTimeout(r, 1000)); // the last DTU's notifications
    const measured = dtus.slice(from, -1);
    stopReader();

    const floor = [];
    const change = [];
    const added = [];
    const sse = [];
    for (const d of measured) {
      const t = changes.get(d.lastRow);
      const s = streamed.get(d.lastRow);
      if (t === undefined || s === undefined) continue;
      floor.push(d.arrival - d.lastRow);
      sse.push(s - d.lastRow);
      change.push(t - d.lastRow);
      added.push(t - d.arrival);
    }
    const rowsSeen = [...changes.keys()].filter((k) => measured.length && k >= measured[0].lastRow - 99 && k <= measured.at(-1).lastRow).length;
    const f = percentiles(floor);
    const ch = percentiles(change);
    const ad = percentiles(added);
    const ss = percentiles(sse);
    const ms = (x) => `${x.toFixed(2)} ms`;
    console.log(`Sample DTU -> OPC UA DataChange, end to end; node ${process.version}; ${measured.length} DTUs of ${CHANNEL} (1 ms rows, 100 ms upload) in ${SECONDS} s; ${ITEM} monitored at sampling ${item.monitoringParameters.samplingInterval} ms (asked ${SAMPLING}); publishing interval ${subscription.publishingInterval} ms (10 asked)`);
    console.log(`  rows reported: ${rowsSeen} of ${measured.length * 100} sampled (a row equal to the one before is not a change)`);
    console.log(`  floor: DTU at a plain MQTT subscriber, after its last row   p50 ${ms(f.p50)}  p99 ${ms(f.p99)}  (n=${f.n})`);
    console.log(`  the row as the bridge's SSE event at a plain HTTP reader    p50 ${ms(ss.p50)}  p99 ${ms(ss.p99)}  (n=${ss.n})`);
    console.log(`  DataChange of the DTU's last row, after that row          p50 ${ms(ch.p50)}  p99 ${ms(ch.p99)}  (n=${ch.n})  ratio to floor p50 ${(ch.p50 / f.p50).toFixed(1)} p99 ${(ch.p99 / f.p99).toFixed(1)}`);
    console.log(`  added by bridge + nclink-opcua + publishing (per DTU)      p50 ${ms(ad.p50)}  p99 ${ms(ad.p99)}  (n=${ad.n})`);
    await subscription.terminate();
    await c.close();
  } finally {
    for (const p of procs.reverse()) await stopProcess(p);
    if (!process.env.KEEP) fs.rmSync(work, { recursive: true, force: true });
    else console.log(`logs kept in ${work}`);
  }
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
