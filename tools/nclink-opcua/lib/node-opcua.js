"use strict";
// The one place that loads node-opcua. The package pins node-opcua-server,
// -client, -address-space and -nodesets (package.json); the certificate
// manager and the logger switch are dependencies of node-opcua-server itself,
// so they are resolved from node-opcua-server's own folder: the very copies
// the server uses (its `instanceof` checks need the same module instance),
// whatever way npm lays out node_modules.
const path = require("node:path");

const serverDir = path.dirname(require.resolve("node-opcua-server/package.json"));
const fromServer = (name) => require(require.resolve(name, { paths: [serverDir] }));

const debug = fromServer("node-opcua-debug");
const server = require("node-opcua-server");
const client = require("node-opcua-client");
const { nodesets } = require("node-opcua-nodesets");
const { generateAddressSpace } = require("node-opcua-address-space/nodeJS");
const { OPCUACertificateManager } = fromServer("node-opcua-certificate-manager");

module.exports = {
  debug,
  OPCUAServer: server.OPCUAServer,
  MonitoredItem: server.MonitoredItem,
  OPCUAClient: client.OPCUAClient,
  OPCUACertificateManager,
  generateAddressSpace,
  nodesets,
  DataType: client.DataType,
  DataValue: client.DataValue,
  Variant: client.Variant,
  VariantArrayType: client.VariantArrayType,
  StatusCodes: client.StatusCodes,
  AttributeIds: client.AttributeIds,
  MonitoringMode: client.MonitoringMode,
  NodeClass: client.NodeClass,
  SecurityPolicy: client.SecurityPolicy,
  MessageSecurityMode: client.MessageSecurityMode,
  UserTokenType: client.UserTokenType,
};
