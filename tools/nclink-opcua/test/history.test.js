"use strict";
// HistoryRead of item variables over the bridge's buffer (docs/opcua.md
// "History"), seen by a node-opcua client: raw values by time range, in the
// variable's DataType with their source time, bad ones Bad, a reversed range
// newest first; the bridge asked with the range.
const { describe, it, before, after } = require("node:test");
const assert = require("node:assert/strict");

const opcua = require("../lib/node-opcua");
const { FakeBridge } = require("./support/fake-bridge");
const { makeNodeset, testDevice } = require("./support/fake-nodeset");
const { freePort, startServer, connect } = require("./support/harness");

const { AttributeIds, DataType } = opcua;
const DEV = "fake-mill-1";
const URI = `urn:nclink:device:${DEV}`;
const T0 = Date.parse("2026-03-01T00:00:00Z");

describe("nclink-opcua history", () => {
  let bridge;
  let server;
  let c;
  let ns;
  const nodeId = (id) => `ns=${ns};s=${id}`;

  before(async () => {
    opcua.debug.setWarningLogger(() => {});
    bridge = new FakeBridge({ pingMs: 300 });
    bridge.addDevice({ dev: DEV, name: "Fake mill", version: "1", nodeset: makeNodeset(testDevice(DEV)), values: {} });
    for (let i = 0; i < 5; i++) bridge.pushValue(DEV, "x_position", 10 + i, { time: T0 + i * 1000 });
    bridge.pushValue(DEV, "x_position", null, { time: T0 + 5000, quality: "bad" });
    bridge.pushValue(DEV, "status", "holding", { time: T0 + 2500 });
    await bridge.start();
    const port = await freePort();
    server = startServer(["--bridge", bridge.url, "--port", String(port), "--reconnect-max", "500"]);
    await server.waitForLine(/device fake-mill-1: serving \d+ items/, { ms: 240000 }); // node-opcua loads slowly on a busy machine
    c = await connect(opcua, `opc.tcp://127.0.0.1:${port}`);
    ns = (await c.session.readNamespaceArray()).indexOf(URI);
  });

  after(async () => {
    if (c) await c.close().catch(() => {});
    if (server) assert.equal((await server.stop()).code, 0);
    if (bridge) await bridge.stop();
  });

  it("every item is Historizing with HistoryRead access", async () => {
    for (const id of ["x_position", "status", "parameters"]) {
      const [historizing, access] = await c.session.read([
        { nodeId: nodeId(id), attributeId: AttributeIds.Historizing },
        { nodeId: nodeId(id), attributeId: AttributeIds.AccessLevel },
      ]);
      assert.equal(historizing.value.value, true, id);
      assert.ok(access.value.value & 0x04, `${id} AccessLevel HistoryRead`);
    }
  });

  it("raw values by time range, both ends included, with the machine's time and DataType", async () => {
    const r = await c.session.readHistoryValue(nodeId("x_position"), new Date(T0 + 1000), new Date(T0 + 3000));
    assert.equal(r.statusCode.name, "Good");
    const values = r.historyData.dataValues;
    assert.deepEqual(values.map((v) => v.value.value), [11, 12, 13]);
    assert.deepEqual(values.map((v) => v.sourceTimestamp.getTime()), [T0 + 1000, T0 + 2000, T0 + 3000]);
    assert.ok(values.every((v) => v.value.dataType === DataType.Double && v.statusCode.name === "Good"));
    const q = bridge.historyRequests.at(-1);
    assert.deepEqual([q.id, Number(q.from), Number(q.to)], ["x_position", T0 + 1000, T0 + 3000]);
  });

  it("an UNAVAILABLE value is Bad; words come as the variable's encoding", async () => {
    const r = await c.session.readHistoryValue(nodeId("x_position"), new Date(T0 + 4500), new Date(T0 + 6000));
    assert.equal(r.historyData.dataValues.length, 1);
    assert.equal(r.historyData.dataValues[0].statusCode.name, "Bad");
    const s = await c.session.readHistoryValue(nodeId("status"), new Date(T0), new Date(T0 + 10000));
    assert.deepEqual(s.historyData.dataValues.map((v) => [v.value.dataType, v.value.value]), [[DataType.UInt32, 2]]); // "holding"
  });

  it("an end before the start reads newest first", async () => {
    const r = await c.session.readHistoryValue(nodeId("x_position"), new Date(T0 + 3000), new Date(T0 + 1000));
    assert.deepEqual(r.historyData.dataValues.map((v) => v.value.value), [13, 12, 11]);
  });
});
