"use strict";
// Sampling intervals of monitored items (docs/opcua.md "Subscriptions and
// sampling"): a client asking a sampling interval at or above an item's
// channel rate (its MinimumSamplingInterval, table B.7) is sampled at the
// interval it asked, not at node-opcua's default floor of 50 ms; nobody is
// sampled faster than the item's channel.
const { describe, it, before, after } = require("node:test");
const assert = require("node:assert/strict");

const opcua = require("../lib/node-opcua");
const { FakeBridge } = require("./support/fake-bridge");
const { makeNodeset, testDevice } = require("./support/fake-nodeset");
const { freePort, startServer, connect, waitUntil } = require("./support/harness");

const { AttributeIds } = opcua;
const DEV = "fake-mill-1";
const URI = `urn:nclink:device:${DEV}`;
const VALUES = 100;
const PERIOD_MS = 10; // 100 Hz: the sampling interval asked

describe("nclink-opcua sampling intervals", () => {
  let bridge;
  let server;
  let c;
  let ns;

  before(async () => {
    opcua.debug.setWarningLogger(() => {});
    const device = testDevice(DEV, {
      extraItems: [{ id: "feed_speed", dataType: "Double", msi: 100, type: "FEED_SPEED" }], // a 100 ms channel's item
    });
    device.components[0].items[0].msi = 1; // x_position in a 1 ms SAMPLE_CHANNEL, as the mapping writes it
    bridge = new FakeBridge({ pingMs: 300 });
    bridge.addDevice({ dev: DEV, name: "Fake mill", version: "1", nodeset: makeNodeset(device), values: { x_position: 0, feed_speed: 0 } });
    await bridge.start();
    const port = await freePort();
    server = startServer(["--bridge", bridge.url, "--port", String(port)]);
    await server.waitForLine(/device fake-mill-1: serving \d+ items/, { ms: 240000 });
    c = await connect(opcua, `opc.tcp://127.0.0.1:${port}`);
    ns = (await c.session.readNamespaceArray()).indexOf(URI);
  });

  after(async () => {
    if (c) await c.close().catch(() => {});
    if (server) assert.equal((await server.stop()).code, 0);
    if (bridge) await bridge.stop();
  });

  const monitor = async (subscription, id, samplingInterval) => {
    const item = await subscription.monitor({ nodeId: `ns=${ns};s=${id}`, attributeId: AttributeIds.Value }, { samplingInterval, queueSize: 1000, discardOldest: true }, 0);
    const seen = [];
    item.on("changed", (dv) => seen.push(dv.value.value));
    return { item, seen, revised: item.monitoringParameters.samplingInterval };
  };

  it("a 10 ms sampling interval on a 1 ms channel's item is kept, and a 100 Hz item reports every value", async () => {
    const subscription = await c.session.createSubscription2({ requestedPublishingInterval: 50, publishingEnabled: true, requestedMaxKeepAliveCount: 20, requestedLifetimeCount: 200 });
    const m = await monitor(subscription, "x_position", 10);
    assert.equal(m.revised, 10, "revised sampling interval: what the client asked, not node-opcua's 50 ms");
    await waitUntil(() => m.seen.includes(0), { what: "the initial value" });
    const values = [];
    const t0 = Date.now();
    for (let i = 1; i <= VALUES; i++) {
      const value = i + 0.5;
      values.push(value);
      bridge.pushValue(DEV, "x_position", value, { time: t0 + i * PERIOD_MS }); // the machine's 100 Hz
      await new Promise((r) => setTimeout(r, PERIOD_MS));
    }
    await waitUntil(() => m.seen.includes(values.at(-1)), { what: "the last value" });
    // Sampled every 50 ms of this process's clock, about 1 value in 5 would be seen.
    assert.deepEqual(m.seen.filter((v) => v !== 0), values, "every value, in order");
    await subscription.terminate();
  });

  it("values closer than the sampling interval in the machine's time are sampled, not all reported", async () => {
    const subscription = await c.session.createSubscription2({ requestedPublishingInterval: 50, publishingEnabled: true, requestedMaxKeepAliveCount: 20, requestedLifetimeCount: 200 });
    const m = await monitor(subscription, "x_position", 10);
    await waitUntil(() => m.seen.length > 0, { what: "the initial value" });
    const t0 = Date.now() + 1000;
    const burst = [];
    for (let i = 0; i < 50; i++) {
      burst.push(1000 + i);
      bridge.pushValue(DEV, "x_position", 1000 + i, { time: t0 + i * 2 }); // 2 ms apart: a 500 Hz run, sent at once
    }
    await waitUntil(() => m.seen.includes(1049), { what: "the last value of the burst" });
    const got = m.seen.filter((v) => v >= 1000);
    // One per 10 ms of the machine's time (1000, 1005, ... 1045), and the
    // last one, which the timer samples; should the run reach the server in
    // several reads, the timer may also take one between them.
    assert.equal(got[0], 1000);
    assert.deepEqual(got, [...got].sort((a, b) => a - b), "in order");
    assert.ok(got.length >= 10 && got.length <= 15, `${got.length} values reported of a 100 ms run sampled at 10 ms: ${got.join(" ")}`);
    await subscription.terminate();
  });

  it("no item is sampled faster than its channel", async () => {
    const subscription = await c.session.createSubscription2({ requestedPublishingInterval: 50, publishingEnabled: true, requestedMaxKeepAliveCount: 20, requestedLifetimeCount: 200 });
    assert.equal((await monitor(subscription, "x_position", 0.5)).revised, 1, "1 ms channel asked 0.5 ms");
    assert.equal((await monitor(subscription, "x_position", 0)).revised, 1, "1 ms channel asked 0 (fastest practical)");
    assert.equal((await monitor(subscription, "feed_speed", 10)).revised, 100, "100 ms channel asked 10 ms");
    assert.equal((await monitor(subscription, "feed_speed", 250)).revised, 250, "100 ms channel asked 250 ms");
    const msi = await c.session.read({ nodeId: `ns=${ns};s=x_position`, attributeId: AttributeIds.MinimumSamplingInterval });
    assert.equal(msi.value.value, 1, "MinimumSamplingInterval stays the channel's rate");
    await subscription.terminate();
  });
});
