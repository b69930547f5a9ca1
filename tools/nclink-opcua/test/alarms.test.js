"use strict";
// NC-Link WARNING values as OPC UA Alarms & Conditions (docs/opcua.md
// "Alarms"), seen by a node-opcua client subscribed to events of the Server
// object and of the device object: raised and cleared as the stream says,
// acknowledged by the client.
const { describe, it, before, after } = require("node:test");
const assert = require("node:assert/strict");

const opcua = require("../lib/node-opcua");
const { constructEventFilter, TimestampsToReturn } = require("node-opcua-client");
const { FakeBridge } = require("./support/fake-bridge");
const { makeNodeset, testDevice } = require("./support/fake-nodeset");
const { freePort, startServer, connect, waitUntil } = require("./support/harness");

const { AttributeIds, DataType, Variant } = opcua;
const DEV = "fake-mill-1";
const URI = `urn:nclink:device:${DEV}`;
const FIELDS = ["EventId", "SourceName", "Message", "Severity", "ConditionName", "ActiveState.Id", "AckedState.Id", "Retain", "ConditionId", "Time"];

describe("nclink-opcua alarms", () => {
  let bridge;
  let server;
  let c;
  let ns;
  const seen = { server: [], device: [] };

  const asObject = (values) => Object.fromEntries(FIELDS.map((f, i) => [f, values[i] ? values[i].value : undefined]));
  const eventsOf = (where, pred) => seen[where].filter(pred);
  const summary = () => Object.entries(seen).map(([where, events]) => `${where}: ${events.map((e) => `${e.ConditionName}/${e["ActiveState.Id"] ? "active" : "inactive"}`).join(" ") || "nothing"}`).join("; ");
  const waitEvent = (where, pred, what) => waitUntil(() => eventsOf(where, pred).at(-1), { ms: 20000, what: `${what} (events seen: ${summary()})` });

  before(async () => {
    opcua.debug.setWarningLogger(() => {});
    bridge = new FakeBridge({ pingMs: 300 });
    bridge.addDevice({ dev: DEV, name: "Fake mill", version: "1", nodeset: makeNodeset(testDevice(DEV)), values: { warning: {} } });
    await bridge.start();
    const port = await freePort();
    server = startServer(["--bridge", bridge.url, "--port", String(port), "--reconnect-max", "500"]);
    await server.waitForLine(/device fake-mill-1: serving \d+ items/, { ms: 240000 }); // node-opcua loads slowly on a busy machine
    c = await connect(opcua, `opc.tcp://127.0.0.1:${port}`);
    ns = (await c.session.readNamespaceArray()).indexOf(URI);
    const subscription = await c.session.createSubscription2({ requestedPublishingInterval: 50, publishingEnabled: true, requestedMaxKeepAliveCount: 20, requestedLifetimeCount: 200 });
    for (const [where, nodeId] of [["server", "i=2253"], ["device", `ns=${ns};s=${DEV}`]]) {
      const item = await subscription.monitor({ nodeId, attributeId: AttributeIds.EventNotifier }, { samplingInterval: 0, queueSize: 1000, filter: constructEventFilter(FIELDS) }, TimestampsToReturn.Neither);
      // node-opcua's client resolves monitor() even when the server refuses
      // the item (it only emits "err"): a refused item would otherwise show
      // up as events that never come.
      assert.equal(item.statusCode.name, "Good", `event monitored item on ${where} (${nodeId})`);
      item.on("changed", (values) => seen[where].push(asObject(values)));
    }
  });

  after(async () => {
    if (c) await c.close().catch(() => {});
    if (server) assert.equal((await server.stop()).code, 0);
    if (bridge) await bridge.stop();
  });

  it("an alarm in the WARNING value is an active AlarmCondition on the device, seen from the Server object too", async () => {
    const t = Date.parse("2026-01-02T03:04:05Z");
    bridge.pushValue(DEV, "warning", [{ number: "1001", text: "X axis following error too large", emerge_time: t }]);
    const raised = await waitEvent("server", (e) => e.ConditionName === "1001" && e["ActiveState.Id"] === true, "1001 active on Server");
    assert.equal(raised.Message.text, "X axis following error too large");
    assert.equal(raised.Severity, 700);
    assert.equal(raised.Retain, true);
    assert.equal(raised["AckedState.Id"], false);
    assert.equal(raised.Time.getTime(), t, "the alarm's emerge_time");
    assert.equal(raised.SourceName, "Fake mill");
    await waitEvent("device", (e) => e.ConditionName === "1001" && e["ActiveState.Id"] === true, "1001 active on the device");
  });

  it("acknowledging it is an OPC UA acknowledgement only, and a cleared acknowledged alarm is no longer retained", async () => {
    const raised = eventsOf("server", (e) => e.ConditionName === "1001" && e["ActiveState.Id"] === true).at(-1);
    const ack = await c.session.call({
      objectId: raised.ConditionId,
      methodId: "i=9111", // AcknowledgeableConditionType.Acknowledge
      inputArguments: [new Variant({ dataType: DataType.ByteString, value: raised.EventId }), new Variant({ dataType: DataType.LocalizedText, value: { text: "seen" } })],
    });
    assert.equal(ack.statusCode.name, "Good");
    await waitEvent("server", (e) => e.ConditionName === "1001" && e["AckedState.Id"] === true, "1001 acknowledged");
    assert.equal(bridge.sets.length + bridge.calls.length, 0, "nothing is sent to the machine");
    bridge.pushValue(DEV, "warning", {});
    const cleared = await waitEvent("server", (e) => e.ConditionName === "1001" && e["ActiveState.Id"] === false, "1001 cleared");
    assert.equal(cleared.Retain, false);
  });

  it("a list raises each alarm; one leaving the list clears only it, retained until acknowledged", async () => {
    bridge.pushValue(DEV, "warning", [{ number: "2010", text: "spindle overload" }, { number: "3005", text: "coolant level low" }]);
    await waitEvent("server", (e) => e.ConditionName === "2010" && e["ActiveState.Id"] === true, "2010 active");
    await waitEvent("server", (e) => e.ConditionName === "3005" && e["ActiveState.Id"] === true, "3005 active");
    const before = eventsOf("server", (e) => e.ConditionName === "3005").length;
    bridge.pushValue(DEV, "warning", [{ number: "3005", text: "coolant level low" }]);
    const cleared = await waitEvent("server", (e) => e.ConditionName === "2010" && e["ActiveState.Id"] === false, "2010 cleared");
    assert.equal(cleared.Retain, true, "not acknowledged: kept for clients that were away");
    await new Promise((r) => setTimeout(r, 300));
    assert.equal(eventsOf("server", (e) => e.ConditionName === "3005").length, before, "3005 unchanged: no new event");
  });
});
