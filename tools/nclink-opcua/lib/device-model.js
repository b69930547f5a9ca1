"use strict";
// One device's namespace once node-opcua has loaded its NodeSet2: finds the
// variable of every NC-Link item, keeps its Value in step with the device's
// cached stream values and link state, and turns OPC UA writes to setable
// items into bridge Sets. Everything here runs on the event loop thread.
const { toVariant, fromVariant } = require("./values");
const { itemStatus, setAnswerStatus, setFailureStatus } = require("./status");
const { stringIdOf } = require("./nodeset-info");
const { addMethods } = require("./methods");
const { DeviceAlarms } = require("./alarms");
const { BridgeHistorian } = require("./history");

const CURRENT_WRITE = 0x02; // AccessLevel bit (OPC 10000-3 8.57)
const PROPERTY_TYPE = "ns=0;i=68";

function textOf(localizedText) {
  return localizedText && typeof localizedText.text === "string" ? localizedText.text : undefined;
}

/// An NC-Link time (wall-clock ms, or an ISO 8601 string) -> Date; now if unusable.
function timeOf(t) {
  const d = typeof t === "number" || typeof t === "string" ? new Date(t) : null;
  return d && !Number.isNaN(d.getTime()) ? d : new Date();
}

class DeviceModel {
  /// entry: the gateway's device record ({dev, cache, link(), linkChangedAt});
  /// info: lib/nodeset-info.js scan of the loaded document.
  constructor({ opcua, addressSpace, entry, info, log, setItem }) {
    this.opcua = opcua;
    this.addressSpace = addressSpace;
    this.entry = entry;
    this.info = info;
    this.log = log;
    this.setItem = setItem; // (dev, id, json) -> Promise<answer>, rejects with BridgeError
    this.items = new Map();
    this.unknownIds = new Set();
    this.methods = []; // UAMethods (addMethods)
    this.alarms = null; // DeviceAlarms (addAlarms)
    this.namespaceIndex = addressSpace.getNamespaceIndex(info.namespaceUris[0]);
    this.availability = this.findVariable(`${entry.dev}.Availability`);
    this.collectItems();
  }

  findVariable(stringId) {
    const node = this.addressSpace.findNode(`ns=${this.namespaceIndex};s=${stringId}`);
    return node && node.nodeClass === this.opcua.NodeClass.Variable ? node : null;
  }

  /// Items named by the nclink:Item extensions; a document without them (not
  /// written by nclink's mapping) has its string-id data variables taken as
  /// items, their encoding read off their properties.
  collectItems() {
    const fromExtensions = this.info.items.size > 0;
    const candidates = fromExtensions
      ? [...this.info.items.values()].map((x) => ({ id: x.id, stringId: x.stringId, nodeId: x.nodeId, encoding: x.encoding }))
      : this.inferredItems();
    for (const c of candidates) {
      const variable = c.stringId === undefined ? null : this.findVariable(c.stringId);
      if (!variable) {
        this.log.warn(`device ${this.entry.dev}: item ${c.id} has no variable ${c.nodeId} in the address space`);
        continue;
      }
      const meta = this.metaOf(variable, c.encoding);
      const item = {
        id: c.id,
        variable,
        meta,
        writable: (variable.accessLevel & CURRENT_WRITE) !== 0,
        initial: this.info.withValue.has(c.nodeId) ? variable.readValue().value : null,
        lastProblem: undefined,
      };
      this.items.set(c.id, item);
      if (item.writable) this.bindWrite(item);
    }
  }

  inferredItems() {
    const ns = this.addressSpace.getNamespace(this.namespaceIndex);
    const out = [];
    for (const node of ns.nodeIterator()) {
      if (node.nodeClass !== this.opcua.NodeClass.Variable) continue;
      const stringId = stringIdOf(node.nodeId.toString().replace(/^ns=\d+;/, ""));
      if (stringId === undefined || stringId.startsWith(`${this.entry.dev}.`)) continue;
      if (node.typeDefinition && node.typeDefinition.toString() === PROPERTY_TYPE) continue;
      let encoding = "scalar";
      if (node.getPropertyByName("EnumStrings")) encoding = "enum_index";
      else if (node.getPropertyByName("TrueState")) encoding = "two_state";
      out.push({ id: stringId, stringId, nodeId: node.nodeId.toString(), encoding });
    }
    return out;
  }

  metaOf(variable, encoding) {
    const { DataType } = this.opcua;
    const basic = variable.getBasicDataType();
    const meta = {
      dataType: basic === DataType.Variant || basic === DataType.Null ? "Variant" : DataType[basic],
      array: variable.valueRank >= 1,
      encoding,
    };
    if (encoding === "enum_index") {
      const p = variable.getPropertyByName("EnumStrings");
      const list = p ? p.readValue().value.value : null;
      meta.enumStrings = Array.isArray(list) ? list.map(textOf) : [];
    } else if (encoding === "two_state") {
      const t = variable.getPropertyByName("TrueState");
      const f = variable.getPropertyByName("FalseState");
      meta.trueState = t ? textOf(t.readValue().value.value) : undefined;
      meta.falseState = f ? textOf(f.readValue().value.value) : undefined;
    }
    return meta;
  }

  /// The DataValue a client sees for `item` now.
  dataValueOf(item) {
    const { StatusCodes, Variant, DataType, VariantArrayType } = this.opcua;
    const link = this.entry.link();
    const cached = this.entry.cache.get(item.id);
    let converted = null;
    let facts = { hasValue: false, quality: "good", empty: false, convertible: true };
    if (cached) {
      converted = toVariant(cached.value, item.meta);
      facts = { hasValue: true, quality: cached.quality, empty: Boolean(converted.empty), convertible: !converted.error };
    } else if (item.initial) {
      facts.hasValue = true;
    }
    const status = itemStatus(link, facts);
    const itemLevel = status === "Good" || status === "BadDeviceFailure" || status === "BadConfigurationError";
    const sourceTimestamp = itemLevel && cached ? timeOf(cached.time) : this.entry.linkChangedAt;
    let value = new Variant({ dataType: DataType.Null });
    if (status === "Good") {
      value = cached
        ? new Variant({
            dataType: DataType[converted.dataType],
            arrayType: converted.array ? VariantArrayType.Array : VariantArrayType.Scalar,
            value: converted.value,
          })
        : item.initial;
    }
    const problem = cached && converted.error ? `value ${JSON.stringify(cached.value)} does not convert: ${converted.error}` : undefined;
    return { value, statusCode: StatusCodes[status], sourceTimestamp, problem };
  }

  /// The model's METHOD configs (lib/methods.js methodsOf) as Methods on the
  /// device object, each calling `call(dev, id, args)`.
  addMethods(methods, call) {
    this.methods = [];
    if (!methods || methods.length === 0) return;
    const deviceNode = this.addressSpace.findNode(`ns=${this.namespaceIndex};s=${this.entry.dev}`);
    if (!deviceNode) {
      this.log.warn(`device ${this.entry.dev}: no device object ns=${this.namespaceIndex};s=${this.entry.dev}; its ${methods.length} method(s) are not offered`);
      return;
    }
    try {
      this.methods = addMethods({ opcua: this.opcua, namespace: this.addressSpace.getNamespace(this.namespaceIndex), deviceNode, dev: this.entry.dev, methods, call, log: this.log });
    } catch (e) {
      this.log.warn(`device ${this.entry.dev}: methods not added: ${e.message}`);
    }
  }

  /// HistoryRead of every item over the bridge's buffer (lib/history.js).
  addHistory(history) {
    let count = 0;
    for (const item of this.items.values()) {
      try {
        const historian = new BridgeHistorian({ opcua: this.opcua, history, dev: this.entry.dev, item, log: this.log });
        this.addressSpace.installHistoricalDataNode(item.variable, { historian });
        count++;
      } catch (e) {
        this.log.warn(`device ${this.entry.dev}: no history for ${item.id}: ${e.message}`);
      }
    }
    this.historized = count;
  }

  /// The WARNING items as Alarms & Conditions on the device object (lib/alarms.js).
  addAlarms() {
    const warnings = [...this.info.items.values()].filter((x) => x.type === "WARNING" && this.items.has(x.id)).map((x) => ({ id: x.id, variable: this.items.get(x.id).variable }));
    if (warnings.length === 0) return;
    const deviceNode = this.addressSpace.findNode(`ns=${this.namespaceIndex};s=${this.entry.dev}`);
    if (!deviceNode) return;
    try {
      this.alarms = new DeviceAlarms({ opcua: this.opcua, addressSpace: this.addressSpace, namespace: this.addressSpace.getNamespace(this.namespaceIndex), deviceNode, dev: this.entry.dev, items: warnings, log: this.log });
    } catch (e) {
      this.log.warn(`device ${this.entry.dev}: alarms not offered: ${e.message}`);
    }
  }

  /// While the device is online its WARNING values raise and clear alarms;
  /// otherwise (offline, bridge unreachable) they stay as last known.
  updateAlarms(item) {
    if (!this.alarms || !this.alarms.has(item.id)) return;
    const link = this.entry.link();
    if (!link.bridgeUp || !link.live || link.state !== "online") return;
    const cached = this.entry.cache.get(item.id);
    if (!cached || cached.quality === "bad") return;
    // Raised on the next check phase (setImmediate), not now. node-opcua
    // schedules a new monitored item's start with setImmediate and answers
    // CreateMonitoredItems Good at once: an event monitored item listens to
    // its object only from that check phase on. A stream value read in the
    // same poll phase as the request (both were waiting when the loop woke:
    // the client answered on the other core while this process was
    // preempted) raised events the new item never saw, although it had been
    // created Good before them; the Server object's older item saw them.
    // Behind that setImmediate, every item created so far listens.
    // Immediates run in order, so the alarms keep the order of the values.
    const value = cached.value;
    const alarms = this.alarms;
    setImmediate(() => {
      if (item.variable.isDisposed && item.variable.isDisposed()) return; // the server was rebuilt since
      try {
        alarms.update(item.id, value);
      } catch (e) {
        this.log.warn(`device ${this.entry.dev}: alarm of ${item.id} not updated: ${e.message}`);
      }
    });
  }

  noteProblem(item, problem) {
    if (problem === item.lastProblem) return;
    item.lastProblem = problem;
    if (problem) this.log.warn(`device ${this.entry.dev}: item ${item.id}: ${problem} (served as BadConfigurationError)`);
  }

  publish(item) {
    if (item.variable.isDisposed && item.variable.isDisposed()) return;
    const dv = this.dataValueOf(item);
    let problem = dv.problem;
    try {
      item.variable.setValueFromSource(dv.value, dv.statusCode, dv.sourceTimestamp);
    } catch (e) {
      // node-opcua refuses a Variant its DataType check does not accept (a
      // DataType the conversion does not know well enough): say so, serve Bad.
      problem = `value not accepted by the variable: ${e.message}`;
      const { Variant, DataType, StatusCodes } = this.opcua;
      item.variable.setValueFromSource(new Variant({ dataType: DataType.Null }), StatusCodes.BadConfigurationError, dv.sourceTimestamp);
    }
    this.noteProblem(item, problem);
    this.updateAlarms(item);
  }

  publishAvailability() {
    if (!this.availability) return;
    const link = this.entry.link();
    const text = link.bridgeUp && link.state === "online" ? "AVAILABLE" : "UNAVAILABLE";
    const { DataType, StatusCodes } = this.opcua;
    this.availability.setValueFromSource({ dataType: DataType.String, value: text }, StatusCodes.Good, this.entry.linkChangedAt);
  }

  /// Every item again (after a snapshot or a link change).
  publishAll() {
    for (const item of this.items.values()) this.publish(item);
    this.publishAvailability();
  }

  /// One item after a stream value; false when the model has no such item.
  publishItem(id) {
    const item = this.items.get(id);
    if (!item) {
      if (!this.unknownIds.has(id)) {
        this.unknownIds.add(id);
        this.log.warn(`device ${this.entry.dev}: value for ${id}, which the nodeset does not have; ignored`);
      }
      return false;
    }
    this.publish(item);
    return true;
  }

  /// Why a write cannot become an NC-Link Set, or undefined. A Set carries a
  /// whole value: no part of one (IndexRange), no status (OPC 10000-4 5.10.4:
  /// BadWriteNotSupported for a combination the server does not support).
  /// Timestamps a client sends are not refused but not kept either: the
  /// variable shows the time of the Set, then the machine's.
  refusalOf(writeValue) {
    const range = writeValue.indexRange;
    const hasRange = range && (typeof range === "string" ? range !== "" : typeof range.isEmpty === "function" ? !range.isEmpty() : true);
    if (hasRange) return "writes of part of a value (IndexRange)";
    const status = writeValue.value && writeValue.value.statusCode;
    if (status && typeof status.isGood === "function" && !status.isGood()) return `a write with status ${status.name}`;
    return undefined;
  }

  bindWrite(item) {
    const model = this;
    const { AttributeIds, StatusCodes } = this.opcua;
    // Checked before node-opcua's own write path: past it, the setter below
    // sees neither the IndexRange nor the status, and would Set the machine.
    const writeAttribute = item.variable.writeAttribute;
    item.variable.writeAttribute = function (context, writeValue, callback) {
      if (writeValue && writeValue.attributeId === AttributeIds.Value) {
        const refusal = model.refusalOf(writeValue);
        if (refusal) {
          model.log.info(`write ${model.entry.dev}/${item.id}: refused, ${refusal} cannot be an NC-Link Set (BadWriteNotSupported)`);
          callback(null, StatusCodes.BadWriteNotSupported);
          return;
        }
      }
      writeAttribute.call(this, context, writeValue, callback);
    };
    item.variable.bindVariable(
      {
        // Reads keep serving what setValueFromSource stored.
        timestamped_get() {
          return this.$dataValue;
        },
        async timestamped_set(dataValue) {
          const status = await model.write(item, dataValue.value);
          // node-opcua stores the DataValue handed to the setter once it returns,
          // whatever the status: hand it the item's value as it now stands, so a
          // refused write leaves the old value and an accepted one shows the
          // converted value with the server's timestamp.
          const now = model.dataValueOf(item);
          dataValue.value = now.value;
          dataValue.statusCode = now.statusCode;
          dataValue.sourceTimestamp = now.sourceTimestamp;
          dataValue.sourcePicoseconds = 0;
          return model.opcua.StatusCodes[status];
        },
      },
      true,
    );
  }

  /// An OPC UA write of `variant` -> status name; the Set goes to the bridge.
  async write(item, variant) {
    const { DataType, VariantArrayType } = this.opcua;
    const dev = this.entry.dev;
    const cached = this.entry.cache.get(item.id);
    const converted = fromVariant(
      { dataType: DataType[variant.dataType], value: variant.value, array: variant.arrayType !== VariantArrayType.Scalar },
      item.meta,
      { wordsSeen: Boolean(cached && typeof cached.value === "string") },
    );
    if (converted.status) {
      this.log.info(`write ${dev}/${item.id}: refused, ${converted.reason} (${converted.status})`);
      return converted.status;
    }
    const shown = JSON.stringify(converted.json);
    let answer;
    try {
      answer = await this.setItem(dev, item.id, converted.json);
    } catch (e) {
      const status = setFailureStatus(e.kind);
      this.log.warn(`write ${dev}/${item.id} = ${shown}: no answer from the bridge, ${e.message} (${status})`);
      return status;
    }
    const status = setAnswerStatus(answer);
    if (status === "Good") {
      this.entry.cache.set(item.id, { value: converted.json, time: Date.now(), quality: "good" });
      this.log.info(`write ${dev}/${item.id} = ${shown}: OK`);
    } else {
      this.log.info(`write ${dev}/${item.id} = ${shown}: NG ${answer.error} ${answer.reason || ""} (${status})`);
    }
    return status;
  }
}

module.exports = { DeviceModel, timeOf };
