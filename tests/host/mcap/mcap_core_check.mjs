// The rig's MCAP files (host/mcap/) read by @mcap/core, the MCAP library Foxglove publishes, with
// its indexed reader (McapIndexedReader: footer, summary, chunk indexes, message indexes) and
// fzstd for the zstd chunks. For each file: the schemas and channels mcap_sample_writer wrote,
// every message read and counted per channel against the Statistics record, times in order, and
// the DataEnd record's CRC-32 equal to one computed here over the data section. The protobuf
// channel is decoded with protobufjs from the FileDescriptorSet stored as its schema, nothing else.
// A run's own log (run.mcap of `hilrig run`) is checked the same way, with every message of every
// channel decoded from its stored schema and the run's channels required.
// With --layout, a Foxglove layout (docs/layouts/hilrig.foxglove.json) is checked against the
// run's log: every message path its panels name (a Plot series, a 3D panel's topic) must be a
// channel of the log, and its field path (array indexes included) must reach a number or a
// boolean in a decoded message of that channel.
// Prints "PASS: FILE: N messages on C channels in K chunks" per file.
// Usage: node mcap_core_check.mjs NODE_MODULES_PARENT [--layout LAYOUT] FILE...
// (a FILE named run.mcap is a run's)
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';

const [modulesParent, ...rest] = process.argv.slice(2);
const layoutAt = rest.indexOf('--layout');
const layoutFile = layoutAt >= 0 ? rest[layoutAt + 1] : undefined;
const files = layoutAt >= 0 ? rest.filter((_, i) => i !== layoutAt && i !== layoutAt + 1) : rest;
const require = createRequire(`${modulesParent}/`);
const { McapIndexedReader } = require('@mcap/core');
const fzstd = require('fzstd');
const protobuf = require('protobufjs');
const descriptor = require('protobufjs/ext/descriptor');

let failures = 0;
function fail(message) {
  console.error(`FAIL: ${message}`);
  failures += 1;
}

const CRC_TABLE = Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; k += 1) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});
function crc32(bytes) {
  let c = 0xffffffff;
  for (const b of bytes) c = CRC_TABLE[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}

function readableOf(bytes) {
  return {
    size: async () => BigInt(bytes.length),
    read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
  };
}

// DataEnd is the last record before the summary: opcode 0x0F, content length 4, the CRC.
function checkDataCrc(name, bytes, summaryStart) {
  const at = Number(summaryStart) - 13;
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  if (bytes[at] !== 0x0f || view.getBigUint64(at + 1, true) !== 4n) {
    fail(`${name}: no DataEnd record before the summary`);
    return;
  }
  const stated = view.getUint32(at + 9, true);
  const computed = crc32(bytes.subarray(0, at));
  if (stated !== computed) fail(`${name}: DataEnd's CRC ${stated} is not the data's ${computed}`);
}

const SAMPLE = {
  topics: ['/plant/state', '/run/events', '/run/report'],
  encodings: ['jsonschema', 'protobuf'],
  minChunks: 2,
};
// balloon_grasp's log: a grasp scene with the pads, and its DUT's traffic (docs/replay.md).
const RUN = {
  topics: ['/checks/altitude_error', '/checks/grasp_force', '/checks/grasp_force_estimate',
    '/checks/held', '/checks/horizontal_error', '/checks/no_burst', '/checks/not_dropped',
    '/dut/estimates', '/dut/in/can', '/dut/in/imu', '/dut/in/setpoint', '/dut/in/step',
    '/dut/in/vio', '/dut/out/command', '/dut/pads', '/plant/grasp', '/plant/pads',
    '/plant/reference_path', '/plant/vehicle', '/run/events', '/run/recording', '/tf'],
  encodings: Array(15).fill('protobuf'),
  minChunks: 2,
  // Foxglove's 3D panel takes these topics for what their schema names say.
  schemaNames: {
    '/tf': 'foxglove.FrameTransform',
    '/plant/reference_path': 'foxglove.PosesInFrame',
    '/checks/grasp_force': 'hilrig.proto.EnvelopeSample',
  },
};

// The message paths of a layout's panels: each Plot series (and custom x axis), each topic a 3D
// panel shows, any other panel's topic path. Each as { panel, text, topic, fields }, fields the
// names and array indexes after the topic ("/plant/pads.force_n[2]": ['force_n', 2]).
function layoutPaths(layout) {
  const paths = [];
  const add = (panel, text) => {
    const dot = text.indexOf('.');
    const topic = dot < 0 ? text : text.slice(0, dot);
    const fields = [];
    if (dot >= 0) {
      const rest = text.slice(dot);
      const token = /\.([A-Za-z_][A-Za-z0-9_]*)|\[(\d+)\]/y;
      let match;
      while (token.lastIndex < rest.length && (match = token.exec(rest)) !== null) {
        fields.push(match[1] ?? Number(match[2]));
      }
      if (token.lastIndex !== rest.length) {
        fail(`layout: ${panel}: cannot parse the message path ${text}`);
        return;
      }
    }
    paths.push({ panel, text, topic, fields });
  };
  for (const [panel, config] of Object.entries(layout.configById ?? {})) {
    for (const series of config.paths ?? []) add(panel, series.value);
    if (config.xAxisPath?.value) add(panel, config.xAxisPath.value);
    if (typeof config.topicPath === 'string' && config.topicPath) add(panel, config.topicPath);
    if (panel.startsWith('3D!')) {
      for (const [topic, settings] of Object.entries(config.topics ?? {})) {
        if (settings.visible) add(panel, topic);
      }
    }
  }
  return paths;
}

// The value a field path reaches in a decoded message, or undefined.
function resolve(decoded, fields) {
  let value = decoded;
  for (const field of fields) {
    if (value === null || typeof value !== 'object') return undefined;
    value = value[field];
  }
  return value;
}

// The sample's reports carry their number; a run's messages need only decode.
function checkDecoded(name, message, decoded) {
  if (message.sequence === undefined || !('scenario' in decoded)) return;
  const expectedSeed = Math.floor(message.sequence / 10);
  if (decoded.scenario !== 'sample' || decoded.seed !== expectedSeed ||
      decoded.envelopes?.[0]?.signal !== 'GRASP_FORCE_N') {
    fail(`${name}: report ${message.sequence} decoded as ${JSON.stringify(decoded)}`);
  }
}

async function check(file) {
  const failuresBefore = failures;
  const bytes = new Uint8Array(readFileSync(file));
  const name = file.split('/').pop();
  const expected = name === 'run.mcap' ? RUN : SAMPLE;
  const reader = await McapIndexedReader.Initialize({
    readable: readableOf(bytes),
    decompressHandlers: { zstd: (buffer) => fzstd.decompress(buffer) },
  });
  const schemas = [...reader.schemasById.values()];
  const topics = [...reader.channelsById.values()].map((c) => c.topic).sort();
  const encodings = schemas.map((s) => s.encoding).sort();
  if (JSON.stringify(encodings) !== JSON.stringify(expected.encodings)) {
    fail(`${name}: schemas ${JSON.stringify(schemas.map((s) => [s.name, s.encoding]))}`);
  }
  if (JSON.stringify(topics) !== JSON.stringify(expected.topics)) {
    fail(`${name}: topics ${topics}`);
  }
  for (const [topic, schemaName] of Object.entries(expected.schemaNames ?? {})) {
    const channel = [...reader.channelsById.values()].find((c) => c.topic === topic);
    const schema = channel && reader.schemasById.get(channel.schemaId);
    if (schema?.name !== schemaName) fail(`${name}: ${topic} is not of ${schemaName}`);
  }
  // Each protobuf channel's type, built from the descriptors stored in the file alone.
  const typeOfChannel = new Map();
  for (const channel of reader.channelsById.values()) {
    const schema = reader.schemasById.get(channel.schemaId);
    if (channel.messageEncoding !== 'protobuf' || schema?.encoding !== 'protobuf') continue;
    const root = protobuf.Root.fromDescriptor(descriptor.FileDescriptorSet.decode(schema.data));
    typeOfChannel.set(channel.id, root.lookupType(schema.name));
  }
  // The layout's paths, each waiting for a message of its topic that it reaches into.
  const unresolved = new Map();  // channel id -> paths not yet reached
  if (expected === RUN && layoutFile) {
    const paths = layoutPaths(JSON.parse(readFileSync(layoutFile, 'utf8')));
    if (paths.length === 0) fail(`${layoutFile}: no message path found`);
    for (const path of paths) {
      const channel = [...reader.channelsById.values()].find((c) => c.topic === path.topic);
      if (!channel) {
        fail(`${layoutFile}: ${path.panel}: ${path.text}: ${name} has no channel ${path.topic}`);
        continue;
      }
      if (!unresolved.has(channel.id)) unresolved.set(channel.id, []);
      unresolved.get(channel.id).push(path);
    }
  }
  const layoutPathCount = [...unresolved.values()].reduce((n, paths) => n + paths.length, 0);
  let decodedReports = 0;
  const stats = reader.statistics;
  if (!stats) {
    fail(`${name}: no Statistics record`);
    return;
  }
  const counts = new Map();
  let total = 0n;
  let last = -1n;
  for await (const message of reader.readMessages()) {
    total += 1n;
    counts.set(message.channelId, (counts.get(message.channelId) ?? 0n) + 1n);
    if (message.logTime < last) fail(`${name}: log times out of order`);
    last = message.logTime;
    const type = typeOfChannel.get(message.channelId);
    if (!type) {
      JSON.parse(new TextDecoder().decode(message.data));
      continue;
    }
    const decoded =
      type.toObject(type.decode(message.data), { longs: Number, enums: String, defaults: true });
    checkDecoded(name, message, decoded);
    decodedReports += 1;
    const waiting = unresolved.get(message.channelId);
    if (waiting?.length) {
      unresolved.set(message.channelId, waiting.filter((path) => {
        // A topic alone (a 3D panel's) is reached by any message; a field path must end on a
        // value a plot can draw.
        if (path.fields.length === 0) return false;
        const value = resolve(decoded, path.fields);
        return typeof value !== 'number' && typeof value !== 'boolean';
      }));
    }
  }
  for (const paths of unresolved.values()) {
    for (const path of paths) {
      fail(`${layoutFile}: ${path.panel}: ${path.text} reaches no number in any message of ` +
        `${path.topic}`);
    }
  }
  if (decodedReports === 0) fail(`${name}: no protobuf message decoded`);
  if (expected === RUN && BigInt(decodedReports) !== total) {
    fail(`${name}: ${decodedReports} of ${total} messages decoded`);
  }
  if (total !== stats.messageCount) {
    fail(`${name}: read ${total}, Statistics say ${stats.messageCount}`);
  }
  for (const [channelId, count] of stats.channelMessageCounts) {
    if (counts.get(channelId) !== count) {
      fail(`${name}: channel ${channelId}: read ${counts.get(channelId)}, Statistics say ${count}`);
    }
  }
  if (reader.chunkIndexes.length !== stats.chunkCount || stats.chunkCount < expected.minChunks) {
    const indexes = reader.chunkIndexes.length;
    fail(`${name}: ${indexes} chunk indexes, Statistics say ${stats.chunkCount}`);
  }
  checkDataCrc(name, bytes, reader.footer.summaryStart);
  if (failures !== failuresBefore) return;
  const layoutNote = layoutPathCount > 0 ? `, the layout's ${layoutPathCount} paths resolved` : '';
  console.log(`PASS: ${name}: ${total} messages on ${counts.size} channels in ` +
    `${stats.chunkCount} chunks, ${decodedReports} decoded from their protobuf schema` +
    layoutNote);
}

for (const file of files) {
  try {
    await check(file);
  } catch (error) {
    fail(`${file}: ${error.stack ?? error}`);
  }
}
process.exit(failures === 0 ? 0 : 1);
