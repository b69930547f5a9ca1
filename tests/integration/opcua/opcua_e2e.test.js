"use strict";
// End to end: mosquitto, the simulated mill (nclink-sim), nclink-bridge and
// nclink-opcua, seen by a node-opcua client and compared with NC-Link Query
// (bin/nclink). Driven from CMake (tests/integration/opcua/CMakeLists.txt),
// which passes the paths in the environment:
//   NCLINK_BIN_DIR    build/bin (nclink, nclink-sim, nclink-bridge)
//   NCLINK_OPCUA_DIR  tools/nclink-opcua (the server and its node_modules)
const { describe, it, before, after } = require("node:test");
const assert = require("node:assert/strict");
const { execFile } = require("node:child_process");
const fs = require("node:fs");
const path = require("node:path");

const BIN = process.env.NCLINK_BIN_DIR;
const OPCUA_DIR = process.env.NCLINK_OPCUA_DIR;
const opcua = require(path.join(OPCUA_DIR, "lib", "node-opcua"));
const { scanNodeset } = require(path.join(OPCUA_DIR, "lib", "nodeset-info"));
const { tempDir, freePort, waitUntil, startServer, connect, browseVariables, spawnLogged: run, stopProcess } = require(path.join(OPCUA_DIR, "test", "support", "harness"));

const { AttributeIds, DataType, Variant } = opcua;
const { constructEventFilter, TimestampsToReturn } = require(require.resolve("node-opcua-client", { paths: [OPCUA_DIR] }));
const DEV = "nclink-sim-mill-01";
const URI = `urn:nclink:device:${DEV}`;

opcua.debug.setWarningLogger(() => {});

async function httpJson(url) {
  const res = await fetch(url);
  if (!res.ok) throw new Error(`${url}: HTTP ${res.status}`);
  return res.json();
}

describe("nclink-opcua with nclink-bridge and the simulated mill", () => {
  const procs = [];
  let work;
  let broker;
  let bridgeUrl;
  let server;
  let c;
  let endpoint; // the server's opc.tcp URL
  let ns;
  let items; // from the bridge's nodeset: id -> {encoding, setable, ...}
  const nodeId = (id) => `ns=${ns};s=${id}`;
  const read = (id) => c.session.read({ nodeId: nodeId(id), attributeId: AttributeIds.Value });
  const write = (id, dataType, value) => c.session.write({ nodeId: nodeId(id), attributeId: AttributeIds.Value, value: { value: { dataType, value } } });

  /// NC-Link Set of `assignments` ("id=<JSON>") at the machine.
  const nclinkSet = (...assignments) =>
    new Promise((resolve, reject) => {
      execFile(path.join(BIN, "nclink"), ["set", "--broker", broker, "--device", DEV, "--timeout", "5000", ...assignments], (err, stdout, stderr) =>
        err ? reject(new Error(`nclink set ${assignments.join(" ")}: ${err.message} ${stdout} ${stderr}`)) : resolve(stdout));
    });

  /// NC-Link Query of `ids` -> Map id -> {code, value}.
  const query = (ids) =>
    new Promise((resolve, reject) => {
      execFile(path.join(BIN, "nclink"), ["query", "--broker", broker, "--device", DEV, "--timeout", "5000", "--json", ...ids], (err, stdout, stderr) => {
        let results;
        try {
          results = JSON.parse(stdout);
        } catch {
          return reject(new Error(`nclink query: ${err ? err.message : ""} ${stderr}`));
        }
        resolve(new Map(results.map((r) => [r.id, { code: r.code, value: Array.isArray(r.values) ? r.values[0] : undefined }])));
      });
    });

  before(async () => {
    work = tempDir("nclink-opcua-e2e-");
    const brokerPort = await freePort();
    broker = `tcp://127.0.0.1:${brokerPort}`;
    fs.writeFileSync(path.join(work, "mosquitto.conf"), `listener ${brokerPort} 127.0.0.1\nallow_anonymous true\nset_tcp_nodelay true\npersistence false\n`);
    const mosquitto = fs.existsSync("/usr/sbin/mosquitto") ? "/usr/sbin/mosquitto" : "mosquitto";
    procs.push(run(mosquitto, ["-c", path.join(work, "mosquitto.conf")], work));
    await waitUntil(async () => {
      const net = require("node:net");
      return new Promise((resolve) => {
        const s = net.connect(brokerPort, "127.0.0.1", () => (s.end(), resolve(true)));
        s.on("error", () => resolve(false));
      });
    }, { what: "mosquitto" });
    // The mill's model with its WARNING item setable: a Set of it is how a
    // test raises an alarm at the machine (docs/simulator.md "Alarms").
    const model = JSON.parse(fs.readFileSync(path.join(OPCUA_DIR, "..", "..", "models", "sim-mill.json"), "utf8"));
    const setWarning = (node) => {
      if (Array.isArray(node)) return node.forEach(setWarning);
      if (!node || typeof node !== "object") return;
      if (node.id === "warning" && node.type === "WARNING") node.setable = true;
      Object.values(node).forEach(setWarning);
    };
    setWarning(model);
    fs.writeFileSync(path.join(work, "sim-mill.json"), JSON.stringify(model));
    procs.push(run(path.join(BIN, "nclink-sim"), ["--broker", broker, "--model", path.join(work, "sim-mill.json"), "--persistence", path.join(work, "sim-state")], work));
    const httpPort = await freePort();
    bridgeUrl = `http://127.0.0.1:${httpPort}`;
    procs.push(run(path.join(BIN, "nclink-bridge"), ["--broker", broker, "--http", `127.0.0.1:${httpPort}`, "--shdr", "off", "--device", DEV], work));
    await waitUntil(async () => {
      const { devices } = await httpJson(`${bridgeUrl}/nclink/v1/devices`);
      return devices.some((d) => d.dev === DEV && d.state === "online");
    }, { ms: 60000, what: "the bridge to see the simulated mill online" });

    // Online comes first, the model (Probe) a moment later: until then the
    // nodeset is 404.
    items = await waitUntil(async () => {
      const res = await fetch(`${bridgeUrl}/nclink/v1/devices/${DEV}/nodeset.xml?profile=basic`);
      const found = res.ok ? scanNodeset(await res.text()).items : new Map();
      return found.size > 10 && found;
    }, { ms: 60000, what: "the bridge's nodeset of the mill" });

    const port = await freePort();
    server = startServer(["--bridge", bridgeUrl, "--port", String(port), "--pki", path.join(work, "pki")]);
    await server.waitForLine(/device nclink-sim-mill-01: serving \d+ items/);
    endpoint = `opc.tcp://127.0.0.1:${port}`;
    c = await connect(opcua, endpoint);
    ns = (await c.session.readNamespaceArray()).indexOf(URI);
    assert.ok(ns > 0, `namespace ${URI} served`);
    // Stop the motion so positions hold still while they are compared, and
    // let loads and currents settle.
    assert.equal((await write("feed_override", DataType.Double, 0)).name, "Good");
    await new Promise((r) => setTimeout(r, 2000));
  });

  after(async () => {
    if (c) await c.close().catch(() => {});
    if (server) await server.stop();
    for (const p of procs.reverse()) await stopProcess(p);
    if (work && !process.env.KEEP) fs.rmSync(work, { recursive: true, force: true });
  });

  it("every mapped item of the mill can be browsed", async () => {
    const found = await browseVariables(opcua, c.session, "i=85", ns);
    for (const id of items.keys()) assert.ok(found.has(id), `item ${id} browsed`);
  });

  it("values agree with NC-Link Query of the same item", async () => {
    const meta = new Map();
    for (const [id, x] of items) {
      const m = { encoding: x.encoding };
      if (x.encoding === "enum_index") {
        const p = await c.session.read({ nodeId: nodeId(`${id}.EnumStrings`), attributeId: AttributeIds.Value });
        m.words = p.value.value.map((t) => t.text);
      } else if (x.encoding === "two_state") {
        m.trueWord = (await c.session.read({ nodeId: nodeId(`${id}.TrueState`), attributeId: AttributeIds.Value })).value.value.text;
      }
      meta.set(id, m);
    }
    // What the OPC UA value should be for a queried NC-Link value (docs/opcua.md "Values").
    const agree = (m, q, ua) => {
      if (m.encoding === "json") return typeof ua === "string" && JSON.stringify(JSON.parse(ua)) === JSON.stringify(q);
      if (m.encoding === "enum_index") return ua === m.words.indexOf(q);
      if (m.encoding === "two_state") return ua === (typeof q === "string" ? q === m.trueWord : Boolean(q));
      if (typeof ua === "number" && typeof q !== "object") return Math.abs(ua - Number(q)) <= 1e-9 * Math.max(1, Math.abs(ua));
      return String(ua) === String(q);
    };
    const ids = [...items.keys()];
    const pending = new Set(ids);
    const problems = new Map();
    const moving = [];
    // The OPC UA side shows the latest value the machine sampled (a sample
    // channel uploads its rows once a second); Query reads the value now.
    // So each round watches every item over 3 s with one Query in the middle:
    // an item agrees when Query gave one of the values watched; an item that
    // moved during the window (noise on loads and currents) agrees when Query
    // lies within what it was seen doing.
    for (let round = 0; round < 3 && pending.size > 0; round++) {
      const seen = new Map([...pending].map((id) => [id, []]));
      const watch = async (ms) => {
        const end = Date.now() + ms;
        while (Date.now() < end) {
          for (const id of pending) seen.get(id).push(await read(id));
          await new Promise((r) => setTimeout(r, 100));
        }
      };
      await watch(1500);
      const answers = await query([...pending]);
      await watch(1500);
      for (const id of [...pending]) {
        const a = answers.get(id);
        const dvs = seen.get(id);
        if (!a || a.code !== "OK") {
          problems.set(id, `Query: ${JSON.stringify(a)}`);
          continue;
        }
        if (a.value === null) {
          // No value at the machine: Bad at the OPC UA side.
          if (dvs.some((dv) => !dv.statusCode.isGood())) pending.delete(id);
          else problems.set(id, `Query null, OPC UA always Good`);
          continue;
        }
        const good = dvs.filter((dv) => dv.statusCode.name === "Good").map((dv) => dv.value.value);
        if (good.some((v) => agree(meta.get(id), a.value, v))) {
          pending.delete(id);
          continue;
        }
        const numbers = good.filter((v) => typeof v === "number");
        if (meta.get(id).encoding === "scalar" && typeof a.value === "number" && numbers.length === good.length && good.length > 1) {
          const lo = Math.min(...numbers);
          const hi = Math.max(...numbers);
          if (hi > lo && a.value >= lo - (hi - lo) && a.value <= hi + (hi - lo)) {
            moving.push(`${id}: Query ${a.value}, OPC UA ${lo}..${hi}`);
            pending.delete(id);
            continue;
          }
        }
        problems.set(id, `Query ${JSON.stringify(a.value)}, OPC UA ${[...new Set(dvs.map((dv) => `${dv.statusCode.name} ${JSON.stringify(dv.value.value)}`))].slice(0, 6).join(" | ")}`);
      }
    }
    if (moving.length) process.stdout.write(`# items that moved, compared by range: ${moving.join("; ")}\n`);
    assert.deepEqual([...pending].map((id) => `${id}: ${problems.get(id)}`), []);
  });

  it("opcua-read (the command-line read the demo uses) prints the served value", async () => {
    const out = await new Promise((resolve) => {
      execFile(process.execPath, [path.join(OPCUA_DIR, "opcua-read.js"), endpoint, DEV, "feed_override", "no_such_item"], (err, stdout, stderr) =>
        resolve({ code: err ? err.code : 0, stdout, stderr }));
    });
    const lines = out.stdout.trim().split("\n");
    assert.match(lines[0], /^feed_override = 0 \(Good, source \d{4}-/, out.stdout + out.stderr);
    assert.match(lines[1], /^no_such_item = null \(BadNodeIdUnknown, source -\)$/, out.stdout + out.stderr);
    assert.equal(out.code, 1, "a read that is not Good makes exit status 1");
  });

  it("a write to a setable item shows in NC-Link Query", async () => {
    assert.ok(items.get("spindle_override").setable);
    assert.equal((await write("spindle_override", DataType.Double, 80)).name, "Good");
    assert.equal((await query(["spindle_override"])).get("spindle_override").value, 80);
    await waitUntil(async () => (await read("spindle_override")).value.value === 80, { what: "the stream to report 80" });
    assert.equal((await write("spindle_override", DataType.Double, 100)).name, "Good");
    assert.equal((await query(["spindle_override"])).get("spindle_override").value, 100);
  });

  it("an out-of-range write is refused with BadOutOfRange, the value stays", async () => {
    // The mill takes overrides 0..150 only (NG 101 Out of Range).
    assert.equal((await write("spindle_override", DataType.Double, 500)).name, "BadOutOfRange");
    await server.waitForLine(/write nclink-sim-mill-01\/spindle_override = 500: NG 101 /, { ms: 5000 });
    assert.equal((await query(["spindle_override"])).get("spindle_override").value, 100);
  });

  it("a write to a read-only item is BadNotWritable", async () => {
    assert.ok(!items.get("x_position").setable);
    assert.equal((await write("x_position", DataType.Double, 1)).name, "BadNotWritable");
  });

  it("profile cnc: the mill's OPC 40502 nodeset loads, every item is there with its value", async () => {
    const port = await freePort();
    const cnc = startServer(["--bridge", bridgeUrl, "--port", String(port), "--pki", path.join(work, "pki-cnc"), "--profile", "cnc"]);
    let s;
    try {
      await cnc.waitForLine(/device nclink-sim-mill-01: serving \d+ items/);
      s = await connect(opcua, `opc.tcp://127.0.0.1:${port}`);
      const namespaces = await s.session.readNamespaceArray();
      assert.ok(namespaces.includes("http://opcfoundation.org/UA/CNC"));
      const cncNs = namespaces.indexOf(URI);
      const found = await browseVariables(opcua, s.session, "i=85", cncNs);
      for (const id of items.keys()) assert.ok(found.has(id), `item ${id} browsed`);
      const dv = await s.session.read({ nodeId: `ns=${cncNs};s=spindle_override`, attributeId: AttributeIds.Value });
      assert.equal(dv.statusCode.name, "Good");
      assert.equal(dv.value.value, 100);
    } finally {
      if (s) await s.close();
      await cnc.stop();
    }
  });
  it("ConditionRefresh and ConditionRefresh2 (OPC 10000-9 5.5.7, 5.5.8) resend the active alarm between RefreshStart and RefreshEnd", async () => {
    const FIELDS = ["EventType", "ConditionName", "ActiveState.Id", "Retain", "Message"];
    const REFRESH_START = "ns=0;i=2787"; // RefreshStartEventType
    const REFRESH_END = "ns=0;i=2788"; // RefreshEndEventType
    const subscription = await c.session.createSubscription2({ requestedPublishingInterval: 50, publishingEnabled: true, requestedMaxKeepAliveCount: 20, requestedLifetimeCount: 200 });
    const events = [];
    try {
      const item = await subscription.monitor({ nodeId: "i=2253", attributeId: AttributeIds.EventNotifier }, { samplingInterval: 0, queueSize: 1000, filter: constructEventFilter(FIELDS) }, TimestampsToReturn.Neither);
      assert.equal(item.statusCode.name, "Good", "event monitored item on the Server object");
      item.on("changed", (values) => events.push(Object.fromEntries(FIELDS.map((f, i) => [f, values[i] ? values[i].value : undefined]))));
      const type = (e) => (e.EventType ? e.EventType.toString() : "");
      const summary = () => events.map((e) => (type(e) === REFRESH_START ? "start" : type(e) === REFRESH_END ? "end" : `${e.ConditionName}/${e["ActiveState.Id"] ? "active" : "inactive"}/retain=${e.Retain}`)).join(" ");

      // An alarm at the machine (the mill raises a Set of its warning item), raised over OPC UA.
      await nclinkSet('warning={"number":"7001","text":"coolant level low"}');
      await waitUntil(() => events.some((e) => e.ConditionName === "7001" && e["ActiveState.Id"] === true), { ms: 20000, what: `alarm 7001 raised (events: ${summary()})` });

      // A client that joins late (or lost its events) asks for the current
      // state: RefreshStart, every retained condition, RefreshEnd.
      const refresh = async (what, methodId, inputArguments) => {
        events.length = 0;
        const result = await c.session.call({ objectId: "i=2782", methodId, inputArguments }); // ConditionType
        assert.equal(result.statusCode.name, "Good", what);
        await waitUntil(() => events.some((e) => type(e) === REFRESH_END), { ms: 10000, what: `${what}: RefreshEndEvent (events: ${summary()})` });
        const start = events.findIndex((e) => type(e) === REFRESH_START);
        const end = events.findIndex((e) => type(e) === REFRESH_END);
        const alarm = events.findIndex((e) => e.ConditionName === "7001");
        assert.ok(start >= 0 && alarm > start && end > alarm, `${what}: RefreshStart, 7001, RefreshEnd in order (events: ${summary()})`);
        assert.equal(events[alarm]["ActiveState.Id"], true, what);
        assert.equal(events[alarm].Retain, true, what);
        assert.equal(events[alarm].Message.text, "coolant level low", what);
      };
      await refresh("ConditionRefresh", "i=3875", [new Variant({ dataType: DataType.UInt32, value: subscription.subscriptionId })]);
      await refresh("ConditionRefresh2", "i=12912", [
        new Variant({ dataType: DataType.UInt32, value: subscription.subscriptionId }),
        new Variant({ dataType: DataType.UInt32, value: item.monitoredItemId }),
      ]);
    } finally {
      await nclinkSet("warning={}").catch(() => {});
      await subscription.terminate().catch(() => {});
    }
  });
});
