"use strict";
// NC-Link WARNING items (GB/T 41970 table 12, value table 14: an alarm
// object {number, text, emerge_time, ...}, a list of them, or {} / [] for
// none) as OPC UA Alarms & Conditions (OPC 10000-9): every active alarm is
// an AlarmConditionType instance on the device object, raised when the
// alarm appears in the item's value and cleared when it leaves it, its
// events reaching subscribers of the device object and of the Server object
// (docs/opcua.md "Alarms"). Everything here runs on the event loop thread.

const SEVERITY = 700; // OPC 10000-9 5.5.2: 601-800 "medium high"; NC-Link alarms carry no severity

/// The active alarms of a WARNING value -> Map<key, {number, text, time}>:
/// key the alarm number (its text when it has none).
function activeAlarms(value) {
  const out = new Map();
  const one = (a) => {
    if (a === null || a === undefined || a === false || a === "" || a === 0) return;
    if (typeof a === "string" || typeof a === "number") {
      out.set(String(a), { number: typeof a === "number" ? String(a) : "", text: typeof a === "string" ? a : "", time: undefined });
      return;
    }
    if (typeof a !== "object" || Array.isArray(a) || Object.keys(a).length === 0) return;
    const number = a.number === undefined || a.number === null ? "" : String(a.number);
    const text = typeof a.text === "string" ? a.text : a.text === undefined ? "" : JSON.stringify(a.text);
    const key = number || text;
    if (!key) return;
    const t = typeof a.emerge_time === "number" || typeof a.emerge_time === "string" ? new Date(a.emerge_time) : undefined;
    out.set(key, { number, text, time: t && !Number.isNaN(t.getTime()) ? t : undefined });
  };
  if (Array.isArray(value)) value.forEach(one);
  else one(value);
  return out;
}

/// A NodeId/BrowseName-safe form of an alarm key.
function safe(key) {
  return String(key).replace(/[^A-Za-z0-9_.-]/g, (c) => `_${c.charCodeAt(0).toString(16).toUpperCase()}`);
}

class DeviceAlarms {
  /// items: [{id, variable}] the WARNING items of the device.
  constructor({ opcua, addressSpace, namespace, deviceNode, dev, items, log }) {
    this.opcua = opcua;
    this.addressSpace = addressSpace;
    this.namespace = namespace;
    this.deviceNode = deviceNode;
    this.dev = dev;
    this.items = new Map(items.map((i) => [i.id, i]));
    this.log = log;
    this.conditions = new Map(); // `${item}/${key}` -> {condition, active, alarm}
    // The device object notifies events (EventNotifier SubscribeToEvents) and
    // is their source; the Server object, root of the event hierarchy (OPC
    // 10000-9 4.4), notifies what the device does (HasNotifier) and has it
    // as an event source (HasEventSource), as a ConditionSource must be.
    deviceNode.setEventNotifier(1);
    const server = addressSpace.rootFolder.objects.server;
    if (deviceNode.getEventSourceOfs().length === 0) {
      server.addReference({ referenceType: "HasNotifier", isForward: true, nodeId: deviceNode.nodeId });
      server.addReference({ referenceType: "HasEventSource", isForward: true, nodeId: deviceNode.nodeId });
    }
  }

  has(id) {
    return this.items.has(id);
  }

  condition(itemId, key, alarm) {
    const id = `${itemId}/${key}`;
    let entry = this.conditions.get(id);
    if (entry) return entry;
    const item = this.items.get(itemId);
    const condition = this.namespace.instantiateAlarmCondition("AlarmConditionType", {
      nodeId: `s=${this.dev}.Alarm.${safe(itemId)}.${safe(key)}`,
      browseName: `${itemId}.${safe(key)}`,
      componentOf: this.deviceNode,
      conditionSource: this.deviceNode,
      conditionName: alarm.number || key,
      inputNode: item.variable,
    });
    condition.setEnabledState(true);
    // SourceName: the device as people know it (its DisplayName), not the
    // namespace-qualified BrowseName node-opcua puts there.
    const shown = this.deviceNode.displayName && this.deviceNode.displayName[0] ? this.deviceNode.displayName[0].text : this.dev;
    condition.sourceName.setValueFromSource({ dataType: this.opcua.DataType.String, value: shown });
    entry = { condition, active: false, alarm };
    this.conditions.set(id, entry);
    return entry;
  }

  /// The item's new value: raises the alarms that appeared, clears those that left.
  update(itemId, value, { online = true } = {}) {
    if (!this.items.has(itemId)) return;
    const now = online ? activeAlarms(value) : new Map();
    for (const [key, alarm] of now) {
      const entry = this.condition(itemId, key, alarm);
      if (entry.active && entry.alarm.text === alarm.text) continue;
      entry.active = true;
      entry.alarm = alarm;
      entry.condition.activateAlarm();
      entry.condition.raiseNewCondition({ message: alarm.text || `alarm ${key}`, severity: SEVERITY, retain: true, time: alarm.time });
      this.log.info(`alarm ${this.dev}/${itemId} ${key}: active (${alarm.text})`);
    }
    for (const [id, entry] of this.conditions) {
      if (!id.startsWith(`${itemId}/`) || !entry.active) continue;
      const key = id.slice(itemId.length + 1);
      if (now.has(key)) continue;
      entry.active = false;
      // Kept (Retain) until acknowledged: a client that was away still sees it.
      const acked = entry.condition.currentBranch().getAckedState();
      const retain = !acked;
      entry.condition.deactivateAlarm(retain);
      entry.condition.raiseNewCondition({ message: `${entry.alarm.text || `alarm ${key}`} (cleared)`, severity: SEVERITY, retain });
      this.log.info(`alarm ${this.dev}/${itemId} ${key}: cleared${online ? "" : " (device not online)"}`);
    }
  }
}

module.exports = { DeviceAlarms, activeAlarms };
