#!/usr/bin/env node
// Reads a tcs trace (an MCAP file) with the reference TypeScript readers of
// @mcap/core and checks that the ecosystem's tools will read it: every
// channel has a schema, every message decodes (JSON channels are parsed, CDR
// channels read by their ros2msg schema with Foxglove's own rosmsg parser
// and CDR reader, as Foxglove Studio reads them, to their last byte),
// and the counts agree between the summary, the indexed reader and the
// streaming reader. A file without its footer (a run killed mid-way) is read
// from the start with the streaming reader, as far as its complete chunks.
//
//   node check.mjs [--complete] FILE
//
// Prints one JSON line {messages, channels, schemas, topics: {topic: count},
// truncated}; exits 1 with the reason on any failure, and with --complete
// also when the file is truncated.
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { parse as parseMessageDefinition } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import zstd from "@foxglove/wasm-zstd";
import { open } from "node:fs/promises";
import { crc32 } from "node:zlib";

const MAGIC = Buffer.from([0x89, 0x4d, 0x43, 0x41, 0x50, 0x30, 0x0d, 0x0a]);

class CheckError extends Error {}
function check(cond, message) {
  if (!cond) throw new CheckError(message);
}

const decompressHandlers = {
  zstd: (buffer, decompressedSize) => zstd.decompress(buffer, Number(decompressedSize)),
};

async function readRange(fh, offset, length) {
  const buf = Buffer.alloc(length);
  const { bytesRead } = await fh.read(buf, 0, length, offset);
  check(bytesRead === length, `short read at ${offset}: ${bytesRead} of ${length} bytes`);
  return buf;
}

// A CDR reader per ros2msg schema, built once.
const cdrReaders = new Map();
function cdrReader(channel, schema) {
  let reader = cdrReaders.get(schema);
  if (!reader) {
    check(schema.encoding === "ros2msg", `${channel.topic}: CDR messages with a "${schema.encoding}" schema`);
    const text = new TextDecoder().decode(schema.data);
    try {
      reader = new MessageReader(parseMessageDefinition(text, { ros2: true }));
    } catch (e) {
      throw new CheckError(`${channel.topic}: schema ${schema.name} does not parse: ${e.message}`);
    }
    cdrReaders.set(schema, reader);
  }
  return reader;
}

// Per-message checks shared by both readers; counts go into `tally`.
function tallyMessage(tally, channels, schemas, message) {
  const channel = channels.get(message.channelId);
  check(channel, `message on unknown channel ${message.channelId}`);
  check(channel.schemaId !== 0, `channel ${channel.id} (${channel.topic}) has no schema`);
  check(schemas.has(channel.schemaId), `channel ${channel.id} (${channel.topic}): schema ${channel.schemaId} not found`);
  if (channel.messageEncoding === "cdr") {
    const reader = cdrReader(channel, schemas.get(channel.schemaId));
    try {
      reader.readMessage(message.data);
    } catch (e) {
      throw new CheckError(`${channel.topic} message ${message.sequence} at ${message.logTime} does not decode: ${e.message}`);
    }
    check(!reader.lastReadHadTrailingBytes(), `${channel.topic} message ${message.sequence}: bytes past its last field`);
  } else if (channel.messageEncoding === "json") {
    const text = new TextDecoder("utf-8", { fatal: true }).decode(message.data);
    try {
      JSON.parse(text);
    } catch (e) {
      throw new CheckError(`${channel.topic} message ${message.sequence} at ${message.logTime} is not JSON: ${e.message}`);
    }
  }
  tally.messages++;
  tally.topics[channel.topic] = (tally.topics[channel.topic] ?? 0) + 1;
}

// The whole file through the indexed reader: footer, summary, chunk indexes.
async function readIndexed(fh, size) {
  const reader = await McapIndexedReader.Initialize({
    readable: {
      size: async () => BigInt(size),
      read: async (offset, length) => readRange(fh, Number(offset), Number(length)),
    },
    decompressHandlers,
  });
  for (const channel of reader.channelsById.values()) {
    check(channel.schemaId !== 0, `channel ${channel.id} (${channel.topic}) has no schema`);
    check(reader.schemasById.has(channel.schemaId), `channel ${channel.id} (${channel.topic}): schema ${channel.schemaId} missing from the summary`);
  }
  const tally = { messages: 0, topics: {} };
  for await (const message of reader.readMessages({ validateCrcs: true })) {
    tallyMessage(tally, reader.channelsById, reader.schemasById, message);
  }
  const stats = reader.statistics;
  check(stats, "no Statistics record");
  check(Number(stats.messageCount) === tally.messages, `Statistics count ${stats.messageCount} messages, the reader found ${tally.messages}`);
  check(stats.chunkCount === reader.chunkIndexes.length, `Statistics count ${stats.chunkCount} chunks, the summary indexes ${reader.chunkIndexes.length}`);
  // Per-channel counts, summed per topic (a topic may have several channels).
  const statsTopics = {};
  for (const [id, count] of stats.channelMessageCounts) {
    const topic = reader.channelsById.get(id)?.topic;
    check(topic !== undefined, `Statistics count messages on unknown channel ${id}`);
    if (count === 0n) continue;
    statsTopics[topic] = (statsTopics[topic] ?? 0) + Number(count);
  }
  check(JSON.stringify(sortKeys(statsTopics)) === JSON.stringify(sortKeys(tally.topics)), "Statistics per-channel counts differ from the messages read");
  // Neither reader checks the Data End CRC: check it here.
  if (reader.dataSectionCrc !== undefined) {
    const dataEnd = Number(reader.dataEndOffset);
    let crc = 0;
    for (let at = 0; at < dataEnd; at += 1 << 20) {
      crc = crc32(await readRange(fh, at, Math.min(1 << 20, dataEnd - at)), crc);
    }
    check(crc === reader.dataSectionCrc, `data section CRC ${crc} (expected ${reader.dataSectionCrc})`);
  }
  return { tally, channels: reader.channelsById.size, schemas: reader.schemasById.size };
}

// From the start, record by record, as far as the bytes go.
async function readStream(fh, size) {
  const reader = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  const channels = new Map();
  const schemas = new Map();
  const tally = { messages: 0, topics: {} };
  const drain = () => {
    let record;
    while ((record = reader.nextRecord())) {
      if (record.type === "Schema") schemas.set(record.id, record);
      else if (record.type === "Channel") channels.set(record.id, record);
      else if (record.type === "Message") tallyMessage(tally, channels, schemas, record);
    }
  };
  for (let at = 0; at < size && !reader.done(); at += 1 << 20) {
    reader.append(await readRange(fh, at, Math.min(1 << 20, size - at)));
    drain();
  }
  for (const channel of channels.values()) {
    check(channel.schemaId !== 0 && schemas.has(channel.schemaId), `channel ${channel.id} (${channel.topic}) has no schema`);
  }
  return { tally, channels: channels.size, schemas: schemas.size, done: reader.done(), leftover: reader.bytesRemaining() };
}

function sortKeys(o) {
  return Object.fromEntries(Object.entries(o).sort(([a], [b]) => (a < b ? -1 : a > b ? 1 : 0)));
}

async function main() {
  const args = process.argv.slice(2);
  const requireComplete = args[0] === "--complete";
  if (requireComplete) args.shift();
  if (args.length !== 1) {
    console.error("usage: node check.mjs [--complete] FILE.mcap");
    process.exit(2);
  }
  const path = args[0];
  await zstd.isLoaded;
  const fh = await open(path, "r");
  try {
    const { size } = await fh.stat();
    check(size >= MAGIC.length && (await readRange(fh, 0, MAGIC.length)).equals(MAGIC), "no MCAP magic at the start");
    const complete = size >= 2 * MAGIC.length && (await readRange(fh, size - MAGIC.length, MAGIC.length)).equals(MAGIC);
    check(complete || !requireComplete, "the file is truncated (no closing magic)");

    const stream = await readStream(fh, size);
    let result;
    if (complete) {
      check(stream.done, `the streaming reader did not reach the footer (${stream.leftover} bytes left over)`);
      const indexed = await readIndexed(fh, size);
      const a = JSON.stringify(sortKeys(indexed.tally.topics));
      const b = JSON.stringify(sortKeys(stream.tally.topics));
      check(a === b, `the indexed reader found ${a}, the streaming reader ${b}`);
      result = indexed;
    } else {
      result = stream;
    }
    console.log(JSON.stringify({
      messages: result.tally.messages,
      channels: result.channels,
      schemas: result.schemas,
      topics: sortKeys(result.tally.topics),
      truncated: !complete,
    }));
  } finally {
    await fh.close();
  }
}

main().catch((e) => {
  console.error(`${process.argv.at(-1)}: ${e instanceof CheckError ? "" : "reader error: "}${e.message}`);
  process.exit(1);
});
