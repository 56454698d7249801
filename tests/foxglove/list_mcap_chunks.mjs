// Lists the chunks of an indexed MCAP file as the reference reader sees them: one line per chunk,
// "chunk OFFSET LENGTH COMPRESSION" (COMPRESSION "none" for uncompressed chunks).
//   node list_mcap_chunks.mjs FILE.mcap
import { McapIndexedReader } from "@mcap/core";
import fs from "node:fs/promises";

const handle = await fs.open(process.argv[2], "r");
const size = BigInt((await handle.stat()).size);
const readable = {
  size: async () => size,
  read: async (offset, length) => {
    const buffer = new Uint8Array(Number(length));
    await handle.read(buffer, 0, Number(length), Number(offset));
    return buffer;
  },
};
const reader = await McapIndexedReader.Initialize({ readable });
for (const c of reader.chunkIndexes)
  console.log(`chunk ${c.chunkStartOffset} ${c.chunkLength} ${c.compression === "" ? "none" : c.compression}`);
await handle.close();
