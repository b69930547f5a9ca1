"use strict";
// Sampling a streamed value in the machine's time (docs/opcua.md
// "Subscriptions and sampling").
//
// node-opcua samples a monitored item on a timer: every samplingInterval it
// reads the variable and reports the value if it changed. The values of a
// SAMPLE_CHANNEL item arrive from the bridge in bursts (one SSE chunk can
// carry several), so a timer of the channel's own rate still sees only the
// last of a burst. Here every value the variable takes (its value_changed
// event, fired synchronously by setValueFromSource) is offered to the
// variable's monitored items too, and recorded when its SourceTimestamp is
// at least the item's sampling interval after the last value the item
// recorded (or its status differs): what a sampler at that interval beside
// the machine would have seen. The timer stays: a value skipped here (less
// than one interval after the last) is still picked up by it if it is the
// latest, and node-opcua's own change test drops the double when both see
// one value. Everything runs on the event loop thread.

class StreamSampling {
  constructor({ opcua }) {
    this.opcua = opcua;
    this.watched = new WeakMap(); // variable -> Set<MonitoredItem>
  }

  /// Follows the monitored items every subscription of `server` creates.
  install(server) {
    server.on("create_session", (session) => {
      session.on("new_subscription", (subscription) => {
        subscription.on("monitoredItem", (monitoredItem) => this.adopt(monitoredItem));
      });
    });
  }

  adopt(monitoredItem) {
    const { NodeClass, AttributeIds } = this.opcua;
    const node = monitoredItem.node;
    if (!node || node.nodeClass !== NodeClass.Variable) return;
    if (!monitoredItem.itemToMonitor || monitoredItem.itemToMonitor.attributeId !== AttributeIds.Value) return;
    let items = this.watched.get(node);
    if (!items) {
      items = new Set();
      this.watched.set(node, items);
      node.on("value_changed", (dataValue, indexRange) => this.offer(items, dataValue, indexRange));
    }
    for (const other of items) if (!other.itemToMonitor) items.delete(other); // disposed
    items.add(monitoredItem);
  }

  offer(items, dataValue, indexRange) {
    const { MonitoringMode } = this.opcua;
    for (const item of items) {
      if (!item.itemToMonitor) {
        items.delete(item); // disposed
        continue;
      }
      // An exception-based item already gets every change from node-opcua;
      // before its timer runs an item has not taken its initial value yet.
      if (item.isExceptionBased || !item.isSampling) continue;
      if (item.monitoringMode !== MonitoringMode.Sampling && item.monitoringMode !== MonitoringMode.Reporting) continue;
      if (!due(item.oldDataValue, dataValue, item.samplingInterval)) continue;
      item.recordValue(dataValue.clone(), false, indexRange || undefined);
    }
  }
}

/// Whether a sampler at `interval` ms would report `next` after `last`.
function due(last, next, interval) {
  if (!last || !last.statusCode || last.statusCode.value !== next.statusCode.value) return true;
  const a = last.sourceTimestamp;
  const b = next.sourceTimestamp;
  if (!a || !b) return true;
  const gap = b.getTime() - a.getTime();
  return gap >= interval || gap < 0; // a clock that went back: a new run of values
}

module.exports = { StreamSampling, due };
