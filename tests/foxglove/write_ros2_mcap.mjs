// Writes a ROS 2 bag in MCAP storage with the reference libraries (@mcap/core for the file, @foxglove/rosmsg
// and @foxglove/rosmsg2-serialization for the CDR messages), as rosbag2's MCAP plugin lays it out: profile
// "ros2", one ros2msg schema per type, cdr channels with their offered QoS, log time = the recorder's
// receive time. The input is either a rosbag2 sqlite3 file (--db3: every message decoded with the reference
// reader and written again with the reference writer) or a capture (--pcap, with --odometry CSV
// utime,x,y,z,qw,qx,qy,qz: its data packets in VelodyneScan messages and the poses as nav_msgs/Odometry).
//
//   node write_ros2_mcap.mjs (--db3 FILE | --pcap FILE [--odometry CSV]) --out FILE.mcap
//        [--compression none|zstd|lz4] [--no-index] [--no-chunks] [--chunk-size BYTES] [--metadata-yaml]
//
// Prints one line: "wrote FILE: N messages on T topics (compression C, indexed yes|no)".
import { McapWriter } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageReader, MessageWriter } from "@foxglove/rosmsg2-serialization";
import { execFileSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";

const SEPARATOR = "=".repeat(80);

// The published definitions of the types ogf reads (velodyne_msgs from ros-drivers/velodyne, the rest from
// ROS 2's common_interfaces), concatenated as rosbag2 stores them.
const DEFINITIONS = {
  "velodyne_msgs/msg/VelodyneScan": [
    "std_msgs/Header header\nVelodynePacket[] packets",
    ["velodyne_msgs/VelodynePacket", "builtin_interfaces/Time stamp\nuint8[1206] data"],
    ["std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id"],
    ["builtin_interfaces/Time", "int32 sec\nuint32 nanosec"],
  ],
  "nav_msgs/msg/Odometry": [
    "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n" +
      "geometry_msgs/TwistWithCovariance twist",
    ["std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id"],
    ["builtin_interfaces/Time", "int32 sec\nuint32 nanosec"],
    ["geometry_msgs/PoseWithCovariance", "Pose pose\nfloat64[36] covariance"],
    ["geometry_msgs/Pose", "Point position\nQuaternion orientation"],
    ["geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z"],
    ["geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1"],
    ["geometry_msgs/TwistWithCovariance", "Twist twist\nfloat64[36] covariance"],
    ["geometry_msgs/Twist", "Vector3 linear\nVector3 angular"],
    ["geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z"],
  ],
  "tf2_msgs/msg/TFMessage": [
    "geometry_msgs/TransformStamped[] transforms",
    ["geometry_msgs/TransformStamped", "std_msgs/Header header\nstring child_frame_id\nTransform transform"],
    ["std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id"],
    ["builtin_interfaces/Time", "int32 sec\nuint32 nanosec"],
    ["geometry_msgs/Transform", "Vector3 translation\nQuaternion rotation"],
    ["geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z"],
    ["geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1"],
  ],
};

// rosbag2's QoS of a recorded topic (the "ros2" profile requires offered_qos_profiles).
const QOS =
  "- history: 3\n  depth: 0\n  reliability: 1\n  durability: 2\n  deadline:\n    sec: 9223372036\n" +
  "    nsec: 854775807\n  lifespan:\n    sec: 9223372036\n    nsec: 854775807\n  liveliness: 1\n" +
  "  liveliness_lease_duration:\n    sec: 9223372036\n    nsec: 854775807\n  avoid_ros_namespace_conventions: false\n";

function schemaText(type) {
  const [main, ...deps] = DEFINITIONS[type];
  return [main, ...deps.map(([name, text]) => `${SEPARATOR}\nMSG: ${name}\n${text}`)].join("\n");
}

function args(argv) {
  const out = { compression: "none", index: true, chunks: true, chunkSize: 1024 * 1024 };
  for (let i = 2; i < argv.length; ++i) {
    const a = argv[i];
    const value = () => argv[++i];
    if (a === "--db3") out.db3 = value();
    else if (a === "--pcap") out.pcap = value();
    else if (a === "--odometry") out.odometry = value();
    else if (a === "--out") out.out = value();
    else if (a === "--compression") out.compression = value();
    else if (a === "--no-index") out.index = false;
    else if (a === "--no-chunks") out.chunks = false;
    else if (a === "--chunk-size") out.chunkSize = Number(value());
    else if (a === "--metadata-yaml") out.metadataYaml = true;
    else throw new Error(`unknown argument ${a}`);
  }
  if (!out.out || (!out.db3 && !out.pcap)) throw new Error("give --db3 FILE or --pcap FILE, and --out FILE");
  return out;
}

// The messages of a rosbag2 sqlite3 file in its reading order (timestamp, id), read with Python's sqlite3.
function db3Messages(file) {
  const py = `
import base64, json, sqlite3, sys
db = sqlite3.connect("file:" + sys.argv[1] + "?mode=ro", uri=True)
topics = {i: (n, t) for i, n, t in db.execute("SELECT id, name, type FROM topics")}
for tid, ts, data in db.execute("SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id"):
    n, t = topics[tid]
    print(json.dumps({"topic": n, "type": t, "timestamp": str(ts), "data": base64.b64encode(data).decode()}))
`;
  const text = execFileSync("python3", ["-c", py, file], { maxBuffer: 1 << 30 }).toString();
  return text
    .split("\n")
    .filter((l) => l.length > 0)
    .map((l) => {
      const m = JSON.parse(l);
      return { topic: m.topic, type: m.type, time: BigInt(m.timestamp), data: Buffer.from(m.data, "base64") };
    });
}

// The UDP datagrams to port 2368 of a classic pcap (Ethernet, optional 802.1Q, IPv4).
function pcapPackets(file) {
  const b = fs.readFileSync(file);
  const le = b.readUInt32LE(0) === 0xa1b2c3d4;
  const u32 = (o) => (le ? b.readUInt32LE(o) : b.readUInt32BE(o));
  const nanos = u32(0) === 0xa1b23c4d;
  const out = [];
  for (let pos = 24; pos + 16 <= b.length; ) {
    const sec = BigInt(u32(pos));
    const frac = BigInt(u32(pos + 4));
    const incl = u32(pos + 8);
    const frame = b.subarray(pos + 16, pos + 16 + incl);
    pos += 16 + incl;
    let eth = 12;
    let type = frame.readUInt16BE(eth);
    if (type === 0x8100) type = frame.readUInt16BE((eth += 4));
    if (type !== 0x0800) continue;
    const ip = eth + 2;
    if (frame[ip + 9] !== 17) continue;
    const udp = ip + (frame[ip] & 0x0f) * 4;
    if (frame.readUInt16BE(udp + 2) !== 2368) continue;
    const payload = frame.subarray(udp + 8, udp + frame.readUInt16BE(udp + 4));
    out.push({ ns: sec * 1000000000n + (nanos ? frac : frac * 1000n), payload });
  }
  return out;
}

function stampOf(ns) {
  return { sec: Number(ns / 1000000000n), nanosec: Number(ns % 1000000000n) };
}

// VelodyneScan messages of 76 packets each (about one revolution of a VLP-16 at 600 rpm), logged at the
// last packet's time as a driver publishes them, and Odometry from the CSV, as nav_msgs/Odometry on /odom.
function captureMessages(pcap, odometry) {
  const out = [];
  const packets = pcapPackets(pcap);
  for (let i = 0; i < packets.length; i += 76) {
    const group = packets.slice(i, i + 76);
    const last = group[group.length - 1].ns;
    out.push({
      topic: "/velodyne_packets",
      type: "velodyne_msgs/msg/VelodyneScan",
      time: last,
      message: {
        header: { stamp: stampOf(group[0].ns), frame_id: "velodyne" },
        packets: group.map((p) => ({ stamp: stampOf(p.ns), data: Uint8Array.from(p.payload) })),
      },
    });
  }
  if (odometry) {
    for (const line of fs.readFileSync(odometry, "utf8").split("\n")) {
      const f = line.trim().split(",");
      if (f.length < 8 || !/^-?\d+$/.test(f[0])) continue;
      const ns = BigInt(f[0]) * 1000n;
      const [x, y, z, qw, qx, qy, qz] = f.slice(1, 8).map(Number);
      out.push({
        topic: "/odom",
        type: "nav_msgs/msg/Odometry",
        time: ns,
        message: {
          header: { stamp: stampOf(ns), frame_id: "odom" },
          child_frame_id: "base_link",
          pose: { pose: { position: { x, y, z }, orientation: { x: qx, y: qy, z: qz, w: qw } }, covariance: new Array(36).fill(0) },
          twist: { twist: { linear: { x: 0, y: 0, z: 0 }, angular: { x: 0, y: 0, z: 0 } }, covariance: new Array(36).fill(0) },
        },
      });
    }
  }
  // A recorder logs in arrival order: by time, packets before poses of the same instant.
  return out.sort((a, b) => (a.time < b.time ? -1 : a.time > b.time ? 1 : 0));
}

class FileWritable {
  constructor(file) {
    this.fd = fs.openSync(file, "w");
    this.offset = 0n;
  }
  async write(buffer) {
    fs.writeSync(this.fd, buffer);
    this.offset += BigInt(buffer.byteLength);
  }
  position() {
    return this.offset;
  }
  close() {
    fs.closeSync(this.fd);
  }
}

async function compressorFor(name) {
  if (name === "none") return undefined;
  if (name === "zstd") {
    const zstd = await import("@foxglove/wasm-zstd");
    await zstd.isLoaded;
    return (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) });
  }
  if (name === "lz4") {
    const lz4 = (await import("lz4js")).default;
    return (data) => ({ compression: "lz4", compressedData: Uint8Array.from(lz4.compress(data)) });
  }
  throw new Error(`--compression ${name}: none, zstd or lz4`);
}

async function main() {
  const o = args(process.argv);
  const writable = new FileWritable(o.out);
  const writer = new McapWriter({
    writable,
    useChunks: o.chunks,
    chunkSize: o.chunkSize,
    compressChunk: o.chunks ? await compressorFor(o.compression) : undefined,
    useStatistics: o.index,
    useChunkIndex: o.index,
    useMessageIndex: o.index,
    useSummaryOffsets: o.index,
    repeatSchemas: o.index,
    repeatChannels: o.index,
  });
  await writer.start({ profile: "ros2", library: "ogf tests: @mcap/core + @foxglove/rosmsg2-serialization" });

  const codecs = new Map();  // type -> { writer, reader }
  const codec = (type) => {
    if (!codecs.has(type)) {
      if (!DEFINITIONS[type]) throw new Error(`no definition of ${type}`);
      const defs = parse(schemaText(type), { ros2: true });
      codecs.set(type, { writer: new MessageWriter(defs), reader: new MessageReader(defs) });
    }
    return codecs.get(type);
  };
  const channels = new Map();  // topic -> channel id
  const channelOf = async (topic, type) => {
    if (!channels.has(topic)) {
      const schemaId = await writer.registerSchema({
        name: type,
        encoding: "ros2msg",
        data: new TextEncoder().encode(schemaText(type)),
      });
      channels.set(topic, await writer.registerChannel({
        topic,
        schemaId,
        messageEncoding: "cdr",
        metadata: new Map([["offered_qos_profiles", QOS]]),
      }));
    }
    return channels.get(topic);
  };

  const input = o.db3 ? db3Messages(o.db3) : captureMessages(o.pcap, o.odometry);
  const counts = new Map();
  let sequence = 0;
  for (const m of input) {
    const c = codec(m.type);
    // From a sqlite3 bag: the message read with the reference reader and written again by the reference writer.
    const message = m.message ?? c.reader.readMessage(m.data);
    const data = c.writer.writeMessage(message);
    await writer.addMessage({
      channelId: await channelOf(m.topic, m.type),
      sequence: sequence++,
      logTime: m.time,
      publishTime: m.time,
      data,
    });
    counts.set(m.topic, (counts.get(m.topic) ?? 0) + 1);
  }
  await writer.end();
  writable.close();

  if (o.metadataYaml) {
    const dir = path.dirname(o.out);
    const topics = [...counts.entries()]
      .map(([t, n]) => {
        const type = input.find((m) => m.topic === t).type;
        return `    - topic_metadata:\n        name: ${t}\n        type: ${type}\n        serialization_format: cdr\n` +
          `        offered_qos_profiles: ""\n      message_count: ${n}`;
      })
      .join("\n");
    fs.writeFileSync(path.join(dir, "metadata.yaml"),
      `rosbag2_bagfile_information:\n  version: 8\n  storage_identifier: mcap\n  relative_file_paths:\n` +
      `    - ${path.basename(o.out)}\n  message_count: ${sequence}\n  topics_with_message_count:\n${topics}\n` +
      `  compression_format: ""\n  compression_mode: ""\n`);
  }
  console.log(`wrote ${o.out}: ${sequence} messages on ${counts.size} topics (compression ${o.compression}, ` +
    `indexed ${o.index ? "yes" : "no"})`);
}

main().catch((e) => {
  console.error(e.stack ?? String(e));
  process.exit(1);
});
