"use strict";
// HistoryRead (OPC 10000-11, raw values by time range) of every item
// variable over what the bridge still buffers of it (GET
// /nclink/v1/devices/{dev}/history; docs/opcua.md "History"): the history
// outlives an OPC UA server restart (a model change) because it is the
// bridge's, and it reaches back as far as the bridge's buffer does.
const { toVariant } = require("./values");

/// ms since the epoch of a HistoryRead time; undefined when unspecified
/// (OPC UA's minimum DateTime, or none).
function msOf(date) {
  if (!(date instanceof Date) || Number.isNaN(date.getTime())) return undefined;
  return date.getTime() <= Date.UTC(1601, 0, 2) ? undefined : date.getTime();
}

/// The node-opcua historian (IVariableHistorian) of one item.
class BridgeHistorian {
  constructor({ opcua, history, dev, item, log }) {
    this.opcua = opcua;
    this.history = history; // (dev, id, fromMs, toMs, max) -> Promise<{values}>
    this.dev = dev;
    this.item = item;
    this.log = log;
  }

  /// The server's own values need no keeping: the bridge has them.
  async push() {}

  /// node-opcua asks for the values between the details' start and end
  /// (it has put an end given before the start first, and then wants the
  /// answer reversed: reverseDataValue). isReversed: no start, so the
  /// newest `maxNumberToExtract` up to the end, newest first.
  extractDataValues(details, maxNumberToExtract, isReversed, reverseDataValue, callback) {
    const from = msOf(details.startTime);
    const to = msOf(details.endTime);
    const wanted = maxNumberToExtract > 0 ? Math.min(maxNumberToExtract, 100000) : 100000;
    this.history(this.dev, this.item.id, isReversed ? undefined : from, to, isReversed ? 100000 : wanted).then(
      (answer) => {
        let values = (Array.isArray(answer.values) ? answer.values : []).map((v) => this.dataValue(v));
        if (isReversed) values = values.slice(-wanted).reverse();
        if (reverseDataValue) values = values.reverse();
        callback(null, values);
      },
      (e) => {
        this.log.warn(`history ${this.dev}/${this.item.id}: ${e.message}`);
        callback(e);
      },
    );
  }

  dataValue(v) {
    const { DataValue, Variant, DataType, StatusCodes, VariantArrayType } = this.opcua;
    const time = new Date(typeof v.time === "number" ? v.time : Date.parse(v.time));
    if (v.value === null || v.value === undefined || v.quality === "bad")
      return new DataValue({ value: new Variant({ dataType: DataType.Null }), statusCode: StatusCodes.Bad, sourceTimestamp: time, serverTimestamp: time });
    const converted = toVariant(v.value, this.item.meta);
    if (converted.error || converted.empty)
      return new DataValue({ value: new Variant({ dataType: DataType.Null }), statusCode: StatusCodes.BadConfigurationError, sourceTimestamp: time, serverTimestamp: time });
    return new DataValue({
      value: new Variant({ dataType: DataType[converted.dataType], arrayType: converted.array ? VariantArrayType.Array : VariantArrayType.Scalar, value: converted.value }),
      statusCode: StatusCodes.Good,
      sourceTimestamp: time,
      serverTimestamp: time,
    });
  }
}

module.exports = { BridgeHistorian, msOf };
