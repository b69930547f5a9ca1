"use strict";
// The devices of one bridge, served by one OPC UA server.
//
// Per device: the latest stream values (cache), the link (bridge stream up,
// device state, snapshot seen) and, once its NodeSet2 is loaded, a
// DeviceModel that shows the cache in the address space. Values are cached
// whether or not the model is loaded yet, so nothing the stream says is lost
// while a nodeset is being fetched.
//
// Address-space changes (loading a device, rebuilding the server after a
// model change) run one at a time on a queue; stream events never wait for
// them. Everything runs on the event loop thread.
const { DeviceModel } = require("./device-model");
const { scanNodeset } = require("./nodeset-info");
const { backoffDelay } = require("./bridge-stream");
const { methodsOf } = require("./methods");

const STATES = new Set(["online", "offline", "unknown"]);

/// reattachAll's way of asking for another fresh server (lib/gateway.js rebuild).
class RevertModel extends Error {}
const LOAD_RETRY_MAX_MS = 30000;

class Gateway {
  constructor({ opcua, options, log, host, bridge, stream }) {
    this.opcua = opcua;
    this.options = options;
    this.log = log;
    this.host = host;
    this.bridge = bridge;
    this.stream = stream;
    this.devices = new Map();
    this.bridgeUp = false;
    this.downSince = undefined; // the stream has been failing since (ms), logged once
    this.queue = Promise.resolve();
    this.stopped = false;
    this.refreshing = null;
  }

  // ------------------------------------------------------------ lifecycle

  async start() {
    await this.host.start();
    this.log.info(`listening on ${this.host.endpointUrls().join(" ")} (security ${this.options.securityPolicies.join(", ")}; anonymous ${this.options.allowAnonymous ? "allowed" : "refused"}; ${this.options.users.length} user(s); pki ${this.options.pki})`);
    this.stream.on("open", () => this.guard(() => this.onStreamOpen()));
    this.stream.on("down", (reason) => this.guard(() => this.onStreamDown(reason)));
    this.stream.on("event", (e) => this.guard(() => this.onEvent(e)));
    this.stream.on("malformed", (e) => this.log.warn(`stream: "${e.type}" event ignored, its data is not JSON (${e.reason})`));
    this.stream.start();
  }

  async stop() {
    this.stopped = true;
    this.stream.stop();
    for (const entry of this.devices.values()) clearTimeout(entry.retryTimer);
    await this.queue.catch(() => {});
    await this.host.stop(0);
    this.bridge.close();
  }

  /// A handler's exception is a bug to log, never a reason to stop serving.
  guard(fn) {
    try {
      fn();
    } catch (e) {
      this.log.error(`internal error: ${e && e.stack ? e.stack : e}`);
    }
  }

  enqueue(what, fn) {
    const run = this.queue.then(async () => {
      if (this.stopped) return;
      try {
        await fn();
      } catch (e) {
        this.log.error(`${what}: ${e && e.message ? e.message : e}`);
      }
    });
    this.queue = run;
    return run;
  }

  // ------------------------------------------------------------ devices

  entryOf(dev) {
    let entry = this.devices.get(dev);
    if (!entry) {
      const gateway = this;
      entry = {
        dev,
        name: "",
        state: "unknown",
        version: undefined, // as last reported by the bridge
        loadedVersion: undefined, // of the nodeset in the address space
        xml: null,
        info: null,
        model: null,
        // The cache holds values of the current stream: after a reconnect, not
        // until the device's snapshot came; a device first heard of on this
        // stream (the bridge announces it with a device event) from the start.
        live: this.bridgeUp,
        cache: new Map(), // item id -> {value, time, quality}
        linkChangedAt: new Date(),
        loadAttempt: 0,
        retryTimer: null,
        failed: null, // {version} whose nodeset did not load
        link() {
          return { bridgeUp: gateway.bridgeUp, state: this.state, live: this.live };
        },
      };
      this.devices.set(dev, entry);
    }
    return entry;
  }

  setState(entry, state, why) {
    const s = STATES.has(state) ? state : "unknown";
    if (s === entry.state) return false;
    entry.state = s;
    entry.linkChangedAt = new Date();
    this.log.info(`device ${entry.dev}: ${s}${why ? ` (${why})` : ""}`);
    return true;
  }

  /// Brings the address space in line with the bridge: loads a device the
  /// first time, rebuilds the server when a loaded device's version changed.
  /// A version whose nodeset did not load is not tried again.
  reconcile(entry) {
    // A nodeset fetched before the bridge told the version is taken as that version.
    if (entry.model && entry.loadedVersion === undefined) entry.loadedVersion = entry.version;
    if (entry.model && entry.version === entry.loadedVersion) return;
    if (entry.failed && entry.failed.version === entry.version) return;
    this.enqueue(`device ${entry.dev}`, async () => {
      if (entry.model && entry.version === entry.loadedVersion) return;
      if (entry.failed && entry.failed.version === entry.version) return;
      let fetched;
      try {
        fetched = await this.fetchNodeset(entry);
      } catch (e) {
        const delay = backoffDelay(entry.loadAttempt++, LOAD_RETRY_MAX_MS, 1000);
        this.log.warn(`device ${entry.dev}: nodeset (version ${entry.version}) not fetched: ${e.message}; retrying in ${delay} ms`);
        clearTimeout(entry.retryTimer);
        entry.retryTimer = setTimeout(() => this.reconcile(entry), delay);
        return;
      }
      entry.loadAttempt = 0;
      // A namespace already in the address space (a loaded model, or what a
      // failed load left) cannot be loaded into again: new server.
      if (entry.model || this.host.addressSpace.getNamespace(fetched.info.namespaceUris[0])) await this.rebuild(entry, fetched);
      else await this.loadDevice(entry, fetched);
    });
  }

  async fetchNodeset(entry) {
    const version = entry.version;
    const xml = await this.bridge.nodeset(entry.dev, this.options.profile);
    const info = scanNodeset(xml);
    if (info.namespaceUris.length === 0) throw new Error("the nodeset declares no namespace");
    const expected = `urn:nclink:device:${entry.dev}`;
    if (info.namespaceUris[0] !== expected)
      this.log.warn(`device ${entry.dev}: nodeset namespace is ${info.namespaceUris[0]}, expected ${expected}`);
    for (const other of this.devices.values())
      if (other !== entry && other.info && other.info.namespaceUris[0] === info.namespaceUris[0])
        throw new Error(`namespace ${info.namespaceUris[0]} is already served for device ${other.dev}`);
    // The METHOD configs become Methods (lib/methods.js); without the model
    // the device is still served, without them.
    let methods = [];
    try {
      methods = methodsOf(await this.bridge.model(entry.dev), entry.dev);
    } catch (e) {
      this.log.warn(`device ${entry.dev}: model not read, no methods offered: ${e.message}`);
    }
    return { xml, info, version, methods };
  }

  loadFailed(entry, version, e) {
    entry.failed = { version };
    this.log.error(`device ${entry.dev}: nodeset (version ${version}) does not load: ${e.message}; that version is not tried again`);
  }

  /// A new device into the running server.
  async loadDevice(entry, fetched) {
    try {
      await this.host.load(`device ${entry.dev}`, fetched.xml);
    } catch (e) {
      this.loadFailed(entry, fetched.version, e);
      return;
    }
    entry.failed = null;
    Object.assign(entry, { xml: fetched.xml, info: fetched.info, loadedVersion: fetched.version, methods: fetched.methods });
    this.attach(entry, this.host.addressSpace);
    if (entry.version !== entry.loadedVersion) this.reconcile(entry);
  }

  attach(entry, addressSpace) {
    entry.model = new DeviceModel({
      opcua: this.opcua,
      addressSpace,
      entry,
      info: entry.info,
      log: this.log,
      setItem: (dev, id, value) => this.bridge.set(dev, id, value),
    });
    entry.model.addMethods(entry.methods, (dev, id, args) => this.bridge.call(dev, id, args));
    entry.model.addAlarms();
    entry.model.addHistory((dev, id, from, to, max) => this.bridge.history(dev, id, from, to, max));
    entry.model.publishAll();
    const writable = [...entry.model.items.values()].filter((i) => i.writable).length;
    this.log.info(`device ${entry.dev}: serving ${entry.model.items.size} items (${writable} writable), ${entry.model.methods.length} methods, ${entry.model.alarms ? entry.model.alarms.items.size : 0} alarm items, in namespace ${entry.info.namespaceUris[0]} (ns=${entry.model.namespaceIndex}, version ${entry.loadedVersion === undefined ? "?" : entry.loadedVersion})`);
  }

  /// A loaded device's model changed: a new server with every device's
  /// current nodeset (node-opcua cannot replace a namespace in place).
  async rebuild(changed, fetched) {
    this.log.info(`device ${changed.dev}: model changed (version ${changed.loadedVersion} -> ${fetched.version}); restarting the OPC UA server to reload it, clients reconnect`);
    const plan = {
      changed,
      previous: changed.xml ? { xml: changed.xml, info: changed.info, loadedVersion: changed.loadedVersion, methods: changed.methods } : null,
    };
    Object.assign(changed, { xml: fetched.xml, info: fetched.info, loadedVersion: fetched.version, methods: fetched.methods });
    for (let attempt = 0; !this.stopped; ) {
      for (const entry of this.devices.values()) entry.model = null;
      try {
        await this.host.restart((addressSpace) => this.reattachAll(addressSpace, plan));
        break;
      } catch (e) {
        if (e instanceof RevertModel) continue; // at once, with the previous model
        const delay = backoffDelay(attempt++, LOAD_RETRY_MAX_MS, 1000);
        this.log.error(`OPC UA server not restarted: ${e.message}; retrying in ${delay} ms`);
        await new Promise((resolve) => setTimeout(resolve, delay));
      }
    }
    if (!this.stopped) this.log.info(`listening again on ${this.host.endpointUrls().join(" ")}`);
  }

  /// Every device's nodeset into a new address space. A changed model that
  /// does not load gives way to the one it replaced: that takes another fresh
  /// address space, as the failed load may have left part of its namespace.
  async reattachAll(addressSpace, plan) {
    for (const entry of this.devices.values()) {
      if (!entry.xml) continue;
      try {
        await this.opcua.generateAddressSpace(addressSpace, [{ name: `device ${entry.dev}`, source: entry.xml }]);
        if (entry.failed && entry.failed.version === entry.loadedVersion) entry.failed = null;
      } catch (e) {
        if (entry !== plan.changed) {
          this.log.error(`device ${entry.dev}: nodeset not reloaded: ${e.message}`);
          continue;
        }
        this.loadFailed(entry, entry.loadedVersion, e);
        if (plan.previous) {
          Object.assign(entry, plan.previous);
          plan.previous = null;
          this.log.info(`device ${entry.dev}: serving version ${entry.loadedVersion} again`);
          throw new RevertModel();
        }
        entry.xml = null;
        continue;
      }
      this.attach(entry, addressSpace);
    }
  }

  /// GET /devices: learn new devices, versions and states.
  refreshDevices() {
    if (this.refreshing) return this.refreshing;
    this.refreshing = (async () => {
      try {
        const list = await this.bridge.devices();
        const listed = new Set();
        for (const d of list) {
          listed.add(d.dev);
          const entry = this.entryOf(d.dev);
          entry.name = typeof d.name === "string" ? d.name : entry.name;
          if (d.version !== undefined) entry.version = d.version;
          // The stream's snapshot is the authority on state once it arrived.
          if (!entry.live && this.setState(entry, d.state, "device list") && entry.model) entry.model.publishAll();
          this.reconcile(entry);
        }
        for (const entry of this.devices.values())
          if (!listed.has(entry.dev) && entry.state !== "unknown") {
            this.setState(entry, "unknown", "no longer listed by the bridge");
            if (entry.model) entry.model.publishAll();
          }
      } catch (e) {
        this.log.warn(`device list not read: ${e.message}`);
      } finally {
        this.refreshing = null;
      }
    })();
    return this.refreshing;
  }

  // ------------------------------------------------------------ stream

  onStreamOpen() {
    this.bridgeUp = true;
    this.log.info(`bridge stream open (${this.options.bridge})`);
    this.downSince = undefined;
    for (const entry of this.devices.values()) {
      entry.linkChangedAt = new Date();
      if (entry.model) entry.model.publishAll();
    }
    this.refreshDevices();
  }

  onStreamDown(reason) {
    const wasUp = this.bridgeUp;
    this.bridgeUp = false;
    for (const entry of this.devices.values()) entry.live = false;
    if (wasUp) {
      this.downSince = Date.now();
      this.log.warn(`bridge stream lost (${reason}); values are BadCommunicationError until it is back`);
      for (const entry of this.devices.values()) {
        entry.linkChangedAt = new Date();
        if (entry.model) entry.model.publishAll();
      }
    } else if (this.downSince === undefined) {
      this.downSince = Date.now();
      this.log.warn(`bridge stream not reachable (${reason}); retrying`);
    }
  }

  onEvent({ type, data }) {
    if (!data || typeof data !== "object" || typeof data.dev !== "string" || data.dev === "") {
      this.log.warn(`stream: "${type}" event without "dev" ignored`);
      return;
    }
    switch (type) {
      case "snapshot":
        return this.onSnapshot(data);
      case "value":
        return this.onValue(data);
      case "device":
        return this.onDevice(data);
      default:
        return undefined; // other event types are not for us
    }
  }

  onSnapshot(data) {
    const entry = this.entryOf(data.dev);
    entry.cache.clear();
    for (const v of Array.isArray(data.values) ? data.values : [])
      if (v && typeof v.id === "string") entry.cache.set(v.id, { value: v.value, time: v.time, quality: v.quality === "bad" ? "bad" : "good" });
    entry.live = true;
    this.setState(entry, data.state, "snapshot");
    entry.linkChangedAt = new Date();
    if (entry.model) entry.model.publishAll();
    // A device first heard of here: learn its version before loading it.
    if (entry.version === undefined) this.refreshDevices().then(() => this.reconcile(entry));
    else this.reconcile(entry);
  }

  onValue(data) {
    if (typeof data.id !== "string") return;
    const entry = this.entryOf(data.dev);
    entry.cache.set(data.id, { value: data.value, time: data.time, quality: data.quality === "bad" ? "bad" : "good" });
    if (entry.model) entry.model.publishItem(data.id);
  }

  onDevice(data) {
    const entry = this.entryOf(data.dev);
    if (data.version !== undefined) entry.version = data.version;
    if (this.setState(entry, data.state, "device event") && entry.model) entry.model.publishAll();
    this.reconcile(entry);
  }
}

module.exports = { Gateway };
