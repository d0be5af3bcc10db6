#!/usr/bin/env node
// Decompresses a LAZ file into the uncompressed LAS it stands for, with laz-perf (the LAZ library
// PDAL uses, built to WASM): the header and variable-length records as they are (the point format's
// compression bits cleared, extended records dropped), then every point record, decoded.
// Usage: node laz_to_las.js IN.laz OUT.las      (exit 1 with a message on stderr when it cannot)
"use strict";
const fs = require("fs");
const { createLazPerf } = require("laz-perf");

function fail(message) {
  process.stderr.write(message + "\n");
  process.exit(1);
}

async function main() {
  const [input, output] = process.argv.slice(2);
  if (!input || !output) fail("usage: node laz_to_las.js IN.laz OUT.las");
  const file = fs.readFileSync(input);
  if (file.length < 227 || file.toString("latin1", 0, 4) !== "LASF") fail("not a LAS/LAZ file (it does not start with 'LASF')");
  const minor = file[25];
  const pointOffset = file.readUInt32LE(96);
  const formatByte = file[104];
  if (!(formatByte & 0xc0)) fail("not compressed: read it as .las");
  if (pointOffset + 8 > file.length) fail("truncated: point data should start at byte " + pointOffset + " but the file has " + file.length + " bytes");
  // LAZ puts the offset of its chunk table first in the point data; it lies inside a whole file.
  const chunkTable = file.readBigInt64LE(pointOffset);
  if (chunkTable > BigInt(file.length))
    fail("truncated: its chunk table should be at byte " + chunkTable + " but the file has " + file.length + " bytes");

  const laz = await createLazPerf();
  const filePtr = laz._malloc(file.length);
  laz.HEAPU8.set(file, filePtr);
  const reader = new laz.LASZip();
  try {
    try {
      reader.open(filePtr, file.length);
    } catch (e) {
      fail("cannot be opened: " + describe(e));
    }
    const count = reader.getCount();
    const length = reader.getPointLength();
    const header = Buffer.from(file.subarray(0, pointOffset));
    header[104] = formatByte & 0x3f;
    if (minor >= 4 && header.length >= 247) {
      header.writeBigUInt64LE(0n, 235);  // no extended variable-length records follow
      header.writeUInt32LE(0, 243);
    }
    const out = fs.openSync(output, "w");
    try {
      fs.writeSync(out, header);
      const batch = 65536;
      const pointPtr = laz._malloc(length * batch);
      try {
        for (let done = 0; done < count; ) {
          const n = Math.min(batch, count - done);
          for (let i = 0; i < n; ++i) {
            try {
              reader.getPoint(pointPtr + i * length);
            } catch (e) {
              fail("point " + (done + i) + " of " + count + " cannot be decoded: " + describe(e));
            }
          }
          fs.writeSync(out, Buffer.from(laz.HEAPU8.buffer, pointPtr, n * length));
          done += n;
        }
      } finally {
        laz._free(pointPtr);
      }
    } finally {
      fs.closeSync(out);
    }
  } finally {
    reader.delete();
    laz._free(filePtr);
  }
}

// What went wrong inside laz-perf: its C++ exceptions reach JavaScript as bare numbers (this build
// cannot tell their message), so those are told as what they mean here.
function describe(e) {
  const text = e && e.message ? String(e.message) : String(e);
  if (typeof e === "number" || /Exception catching is disabled/.test(text))
    return "the LAZ data is truncated or corrupt";
  return text;
}

main().catch((e) => fail(e && e.message ? e.message : String(e)));
