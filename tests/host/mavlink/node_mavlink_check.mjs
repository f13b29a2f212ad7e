// The rig's MAVLink codec against node-mavlink, an implementation generated from the same message
// definitions by other people. Both directions, for every message the codec knows:
//   1. the rig writes a telemetry log (mavlink_vectors tlog); node-mavlink splits its frames, must
//      find every checksum valid, and decodes each field to the value the rig says it wrote;
//   2. node-mavlink encodes each message with distinct field values (and an all-zero
//      HIL_ACTUATOR_CONTROLS, which it sends with a zero-length payload), with garbage between
//      frames; the rig's parser (mavlink_vectors read) must decode every field to the same value.
//   3. with RUN_TLOGs, runs' mavlink.tlog: node-mavlink finds every frame valid, the rate 250 Hz,
//      each HIL_SENSOR answered at its own time and its estimates reported with it; in hover's
//      log the accelerometer at rest reads -g in m/s² along FRD, the magnetometer, barometer and
//      GNSS come at their rates with plausible values; in load_ramp's the tactile
//      frames travel as CAN_FRAME and the grasp as MAV_CMD_DO_GRIPPER with its 4 N set-point.
// Usage: node node_mavlink_check.mjs NODE_MODULES_PARENT MAVLINK_VECTORS WORK_DIR
//          [hover=RUN_TLOG] [load_ramp=RUN_TLOG]
import { execFileSync } from 'node:child_process';
import { readFileSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { PassThrough } from 'node:stream';

const [modulesParent, vectorsBin, workDir, ...runTlogs] = process.argv.slice(2);
const require = createRequire(`${modulesParent}/`);
const mavlink = require('node-mavlink');
const REGISTRY = { ...mavlink.minimal.REGISTRY, ...mavlink.common.REGISTRY };

let failures = 0;
function fail(message) {
  console.error(`FAIL: ${message}`);
  failures += 1;
}

function elementType(field) { return field.type.replace('[]', ''); }

// Equal as the wire type holds it: floats as float32, 64-bit integers as decimal strings.
function same(field, expected, actual) {
  const type = elementType(field);
  if (type === 'float') return Math.fround(Number(expected)) === Math.fround(Number(actual));
  if (type.endsWith('int64_t')) return String(expected) === String(actual);
  return Number(expected) === Number(actual);
}

// A char array as text: node-mavlink reads and writes a string, the rig an array of byte values;
// both stop at the first NUL.
function textOf(value) {
  if (typeof value === 'string') return value.replace(/\0.*$/s, '');
  const end = value.indexOf(0);
  return String.fromCharCode(...(end < 0 ? value : value.slice(0, end)).map(Number));
}

function compareFields(where, clazz, expectedBySource, actualBySource) {
  const sources = clazz.FIELDS.map((field) => field.source);
  for (const name of Object.keys(expectedBySource)) {
    if (!sources.includes(name)) fail(`${where}: the rig has field ${name}, node-mavlink does not`);
  }
  for (const field of clazz.FIELDS) {
    if (!(field.source in expectedBySource)) {
      fail(`${where}: node-mavlink has field ${field.source}, the rig does not`);
      continue;
    }
    const expected = expectedBySource[field.source];
    const actual = actualBySource[field.source];
    const ok = elementType(field) === 'char' ? textOf(expected) === textOf(actual)
      : field.length
      ? expected.length === actual.length && expected.every((e, i) => same(field, e, actual[i]))
      : same(field, expected, actual);
    if (!ok) fail(`${where}.${field.source}: expected ${expected}, got ${actual}`);
  }
}

// The frames of a .tlog and their timestamps: 8 bytes big-endian, then a v2 frame.
function tlogRecords(log) {
  const records = [];
  for (let offset = 0; offset + 18 <= log.length;) {
    const size = 10 + log[offset + 9] + 2 + (log[offset + 10] & 1 ? 13 : 0);
    records.push({ timeUs: log.readBigUInt64BE(offset),
                   frame: log.subarray(offset + 8, offset + 8 + size) });
    offset += 8 + size;
  }
  return records;
}

async function splitFrames(bytes) {
  const splitter = new mavlink.MavLinkPacketSplitter();
  const reader = splitter.pipe(new mavlink.MavLinkPacketParser());
  const packets = [];
  reader.on('data', (packet) => packets.push(packet));
  const input = new PassThrough();
  input.pipe(splitter);
  input.end(bytes);
  await new Promise((resolve) => reader.on('end', resolve));
  return { packets, valid: splitter.validPackages, invalid: splitter.invalidPackages };
}

// 1. The rig's telemetry log, read by node-mavlink.
async function checkRigLog() {
  const tlogPath = `${workDir}/vectors.tlog`;
  const expected = JSON.parse(execFileSync(vectorsBin, ['tlog', tlogPath]).toString());
  const log = readFileSync(tlogPath);
  const frames = [];
  for (let offset = 0, index = 0; offset < log.length; index += 1) {
    const timeUs = log.readBigUInt64BE(offset);
    if (String(timeUs) !== expected[index].time_us) {
      fail(`record ${index}: timestamp ${timeUs}, expected ${expected[index].time_us}`);
    }
    const size = 10 + log[offset + 9] + 2 + (log[offset + 10] & 1 ? 13 : 0);
    frames.push(log.subarray(offset + 8, offset + 8 + size));
    offset += 8 + size;
  }
  const { packets, valid, invalid } = await splitFrames(Buffer.concat(frames));
  if (packets.length !== expected.length || valid !== expected.length || invalid !== 0) {
    fail(`the rig's log: ${packets.length} packets (${valid} valid, ${invalid} invalid), ` +
         `expected ${expected.length} valid`);
  }
  packets.forEach((packet, index) => {
    const want = expected[index];
    const clazz = REGISTRY[packet.header.msgid];
    if (!want || packet.header.msgid !== want.id || !clazz) {
      fail(`packet ${index}: message ${packet.header.msgid}, expected ${want && want.id}`);
      return;
    }
    const data = packet.protocol.data(packet.payload, clazz);
    const actual = {};
    for (const field of clazz.FIELDS) actual[field.source] = data[field.name];
    compareFields(`the rig's ${want.name}`, clazz, want.fields, actual);
  });
  console.log(`node-mavlink read the rig's ${packets.length} frames`);
}

// A distinct value for element `element` of field number `index`, of the field's type.
function valueFor(field, index, element) {
  const k = 5 * index + element + 2;
  switch (elementType(field)) {
    case 'float': return Math.fround(k * 0.75 - 2.2);
    case 'double': return k * 0.3 - 1;
    case 'uint64_t': return 1234567890123n + BigInt(k);
    case 'int64_t': return -987654321n - BigInt(k);
    case 'uint32_t': return 3000000000 + k;
    case 'int32_t': return -20000 * k;
    case 'uint16_t': return 50000 + k;
    case 'int16_t': return -200 * k;
    case 'int8_t': return -k;
    default: return (100 + k) % 256;
  }
}

// 2. node-mavlink's frames, read by the rig.
function checkNodeFrames(ids) {
  const protocol = new mavlink.MavLinkProtocolV2(7, 42);
  const sent = [];
  const chunks = [Buffer.from([0x00, 0xfd, 0x13, 0x37])];  // garbage and a false start first
  ids.forEach((id, sequence) => {
    const clazz = REGISTRY[id];
    const message = new clazz();
    const values = {};
    clazz.FIELDS.forEach((field, index) => {
      const value = elementType(field) === 'char'
        ? `f${index}-${clazz.MSG_ID}`.slice(0, field.length)
        : field.length
        ? Array.from({ length: field.length }, (_, e) => valueFor(field, index, e))
        : valueFor(field, index, 0);
      message[field.name] = value;
      values[field.source] = value;
    });
    sent.push({ clazz, values });
    chunks.push(protocol.serialize(message, sequence), Buffer.from([0x55]));
  });
  const zero = new mavlink.common.HilActuatorControls();
  zero.timeUsec = 0n;
  zero.flags = 0n;
  zero.controls = Array(16).fill(0);
  zero.mode = 0;
  const zeroFrame = protocol.serialize(zero, ids.length);
  chunks.push(zeroFrame);
  const zeroValues = { time_usec: 0n, flags: 0n, controls: Array(16).fill(0), mode: 0 };
  sent.push({ clazz: mavlink.common.HilActuatorControls, values: zeroValues });

  const streamPath = `${workDir}/node_frames.bin`;
  writeFileSync(streamPath, Buffer.concat(chunks));
  const read = JSON.parse(execFileSync(vectorsBin, ['read', streamPath]).toString());
  if (read.frames.length !== sent.length || read.counters.crc_failures !== 0) {
    fail(`the rig read ${read.frames.length} of node-mavlink's ${sent.length} frames ` +
         `(${JSON.stringify(read.counters)})`);
  }
  read.frames.forEach((frame, index) => {
    const { clazz, values } = sent[index] || {};
    if (!clazz || frame.id !== clazz.MSG_ID) {
      fail(`frame ${index}: message ${frame.id}, expected ${clazz && clazz.MSG_ID}`);
      return;
    }
    compareFields(`node-mavlink's ${frame.name}`, clazz, values, frame.fields);
  });
  console.log(`the rig read node-mavlink's ${read.frames.length} frames ` +
              `(the all-zero one with a ${zeroFrame[1]}-byte payload), ` +
              `${read.counters.bytes_skipped} garbage bytes skipped`);
}

// 3. A run's log, as a ground tool would read it.
async function checkRunLog(scene, path) {
  const records = tlogRecords(readFileSync(path));
  const { packets, valid, invalid } =
    await splitFrames(Buffer.concat(records.map((record) => record.frame)));
  if (packets.length !== records.length || valid !== records.length || invalid !== 0) {
    fail(`the run's log: ${records.length} records, node-mavlink found ${valid} valid and ` +
         `${invalid} invalid frames`);
  }
  const allowed = new Set([0, 76, 77, 84, 93, 107, 113, 331, 350, 386]);
  const sensorTimes = [];
  const answered = new Set();
  const estimated = new Set();
  const grasps = [];
  let canFrames = 0;
  let firstZacc = null;
  const magGauss = [];
  const pressuresHpa = [];
  const fixes = [];
  records.slice(1).forEach((record, index) => {
    if (record.timeUs < records[index].timeUs) fail(`the log's time goes back at record ${index + 1}`);
  });
  for (const packet of packets) {
    const id = packet.header.msgid;
    if (!allowed.has(id)) fail(`the run's log holds message ${id}, which the link never sends`);
    const clazz = REGISTRY[id];
    if (!clazz) continue;
    const data = packet.protocol.data(packet.payload, clazz);
    if (id === 107) {
      sensorTimes.push(data.timeUsec);
      if (firstZacc === null) firstZacc = data.zacc;
      // HIL_SENSOR_UPDATED_FLAGS: the magnetometer's three bits, the barometer's three.
      if ((data.fieldsUpdated & 0x1c0) === 0x1c0) magGauss.push(Math.hypot(data.xmag, data.ymag, data.zmag));
      if ((data.fieldsUpdated & 0x1a00) === 0x1a00) pressuresHpa.push(data.absPressure);
    }
    if (id === 113) fixes.push(data);
    if (id === 93) answered.add(String(data.timeUsec));
    if (id === 350 && data.name === 'hilrig' && data.arrayId === 1) {
      estimated.add(String(data.timeUsec));
    }
    if (id === 386) canFrames += 1;
    if (id === 76 && data.command === 211) grasps.push([data._param2, data._param3]);
  }
  if (sensorTimes.length < 2) fail(`the run's log has ${sensorTimes.length} HIL_SENSOR`);
  sensorTimes.slice(1).forEach((time, index) => {
    if (time - sensorTimes[index] !== 4000n) {
      fail(`HIL_SENSOR ${index + 1} comes ${time - sensorTimes[index]} us after the one before, ` +
           'not 4000 (250 Hz)');
    }
  });
  const unanswered = sensorTimes.filter((time) => !answered.has(String(time)));
  if (unanswered.length > 0) {
    fail(`${unanswered.length} HIL_SENSOR without a HIL_ACTUATOR_CONTROLS of their time`);
  }
  const unestimated = sensorTimes.filter((time) => !estimated.has(String(time)));
  if (unestimated.length > 0) {
    fail(`${unestimated.length} HIL_SENSOR without the DUT's estimates (DEBUG_FLOAT_ARRAY hilrig)`);
  }
  if (scene === 'hover') {
    // At rest the accelerometer reads the ground's push: -g along FRD's z, in m/s².
    if (!(firstZacc < -9.3 && firstZacc > -10.3)) {
      fail(`the first HIL_SENSOR's zacc is ${firstZacc}, not about -9.81 m/s² (FRD at rest)`);
    }
    // The magnetometer at 100 Hz reads the default Earth field, 0.48 G; the barometer at 50 Hz
    // the standard atmosphere near Zürich's 408 m (966 hPa); GNSS at 10 Hz there.
    const seconds = sensorTimes.length / 250;
    if (Math.abs(magGauss.length - 100 * seconds) > 2) fail(`${magGauss.length} magnetometer readings`);
    if (magGauss.some((g) => Math.abs(g - 0.48) > 0.01)) fail('a magnetometer reading is not ~0.48 G');
    if (Math.abs(pressuresHpa.length - 50 * seconds) > 2) fail(`${pressuresHpa.length} barometer readings`);
    if (pressuresHpa.some((p) => p < 960 || p > 968)) fail('a barometer reading is not ~966 hPa');
    if (Math.abs(fixes.length - 10 * seconds) > 2) fail(`${fixes.length} HIL_GPS`);
    if (fixes.some((fix) => Math.abs(fix.lat - 473769000) > 1000 || fix.fixType !== 3)) {
      fail('a HIL_GPS is not a 3D fix at the default origin, 47.3769 N');
    }
  }
  if (scene === 'load_ramp') {
    if (canFrames < 1000) fail(`load_ramp's log has ${canFrames} CAN_FRAME, not the tactile traffic`);
    // The scene grasps once, at 4 N: GRIPPER_ACTION_GRAB with the set-point in param3.
    if (!grasps.some(([action, force]) => action === 1 && Math.abs(force - 4) < 1e-6)) {
      fail(`load_ramp's log has no MAV_CMD_DO_GRIPPER grab at 4 N (${JSON.stringify(grasps)})`);
    }
  }
  console.log(`node-mavlink read ${scene}'s ${packets.length} frames: ${sensorTimes.length} ` +
              `HIL_SENSOR at 250 Hz, each answered with its estimates (${magGauss.length} with ` +
              `the magnetometer, ${pressuresHpa.length} with the barometer); ${fixes.length} ` +
              `HIL_GPS; ${canFrames} CAN_FRAME, ${grasps.length} gripper commands`);
}

const expectedIds = JSON.parse(execFileSync(vectorsBin, ['tlog', `${workDir}/ids.tlog`]).toString())
  .map((frame) => frame.id);
await checkRigLog();
checkNodeFrames(expectedIds);
for (const argument of runTlogs) {
  const [scene, path] = argument.split('=');
  await checkRunLog(scene, path);
}
if (failures > 0) {
  console.error(`${failures} mismatches`);
  process.exit(1);
}
console.log('node-mavlink and the rig agree on every field of every message');
