#!/usr/bin/env node
"use strict";
// opcua-read: reads NC-Link items from an OPC UA server, as any OPC UA client
// would, so a plant engineer can check what nclink-opcua serves without a GUI
// client. Security None, anonymous (the defaults of nclink-opcua).
//   node opcua-read.js opc.tcp://127.0.0.1:4840 DEVICE ID [ID...]
// Prints one line per item: `ID = VALUE (STATUS, source TIME)`.
// Exit status: 0 every read Good, 1 a read not Good or the server unreachable,
// 2 usage error.
const opcua = require("./lib/node-opcua");

const usage = "usage: opcua-read.js ENDPOINT DEVICE ID [ID...]\n" +
  "  ENDPOINT  e.g. opc.tcp://127.0.0.1:4840\n" +
  "  DEVICE    the NC-Link device id (namespace urn:nclink:device:DEVICE)\n" +
  "  ID        an NC-Link data item id (node ns=<DEVICE's namespace>;s=ID)";

function show(value) {
  if (value === null || value === undefined) return "null";
  if (typeof value === "object" && value.text !== undefined) return JSON.stringify(value.text);
  if (typeof value === "string") return JSON.stringify(value);
  return String(value);
}

async function main(argv) {
  if (argv.length < 3 || argv.includes("--help")) {
    console.error(usage);
    return argv.includes("--help") ? 0 : 2;
  }
  const [endpoint, device, ...ids] = argv;
  opcua.debug.setWarningLogger(() => {});
  const client = opcua.OPCUAClient.create({
    endpointMustExist: false,
    connectionStrategy: { maxRetry: 0 },
  });
  try {
    await client.connect(endpoint);
  } catch (e) {
    console.error(`opcua-read: cannot connect to ${endpoint}: ${e.message.split("\n")[0]}`);
    return 1;
  }
  let status = 0;
  try {
    const session = await client.createSession();
    const uri = `urn:nclink:device:${device}`;
    const ns = (await session.readNamespaceArray()).indexOf(uri);
    if (ns < 0) {
      console.error(`opcua-read: the server has no namespace ${uri} (device not served)`);
      status = 1;
    } else {
      const values = await session.read(ids.map((id) => ({ nodeId: `ns=${ns};s=${id}`, attributeId: opcua.AttributeIds.Value })));
      values.forEach((dv, i) => {
        const when = dv.sourceTimestamp ? dv.sourceTimestamp.toISOString() : "-";
        console.log(`${ids[i]} = ${show(dv.value && dv.value.value)} (${dv.statusCode.name}, source ${when})`);
        if (!dv.statusCode.isGood()) status = 1;
      });
    }
    await session.close();
  } finally {
    await client.disconnect();
  }
  return status;
}

main(process.argv.slice(2)).then(
  (code) => process.exit(code),
  (e) => {
    console.error(`opcua-read: ${e.message.split("\n")[0]}`);
    process.exit(1);
  },
);
