// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Reads a LAS file with two readers that share no code with bimslam's and prints, as JSON on
// stdout, what each found, point by point (the tests compare it with map_bim.ply):
// - loaders.gl (vis.gl's LAZRsLoader: its LAS 1.4 parser; the default LAZPerfLoader reads LAS up
//   to 1.3 only): positions and classes;
// - copc (Hobu's COPC/LAS reader): the header, the VLRs, the Extra Bytes VLR and the dimensions
//   of point format 6 the tests compare, extra bytes included.
// Usage: node check.mjs FILE.las
import {readFileSync} from 'node:fs';
import {parse} from '@loaders.gl/core';
import {LAZRsLoader} from '@loaders.gl/las';
import {Las} from 'copc';

const file = process.argv[2];
if (!file) {
    console.error('usage: node check.mjs FILE.las');
    process.exit(2);
}
const bytes = readFileSync(file);
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);

// LAZRsLoader starts its WebAssembly module by fetch()ing a file: URL, which Node's fetch does not
// do: start it from the file's bytes first (the package's own module, so the loader finds it set).
const wasmDir = new URL('./node_modules/@loaders.gl/las/dist/libs/laz-rs-wasm/', import.meta.url);
const lazRs = await import(new URL('laz_rs_wasm.js', wasmDir));
await lazRs.default({module_or_path: readFileSync(new URL('laz_rs_wasm_bg.wasm', wasmDir))});

const mesh = await parse(buffer, LAZRsLoader, {worker: false});
const loadersGl = {
    points: mesh.header.vertexCount,
    version: mesh.loaderData.versionAsString,
    format: mesh.loaderData.pointsFormatId,
    // POSITION is float32 relative to nothing: metres as loaders.gl gives them.
    position: Array.from(mesh.attributes.POSITION.value),
    classification: Array.from(mesh.attributes.classification.value),
};

const u8 = new Uint8Array(buffer);
const get = async (begin, end) => u8.slice(begin, end);
const header = Las.Header.parse(u8);
const vlrs = await Las.Vlr.walk(get, header);
const ebVlr = Las.Vlr.find(vlrs, 'LASF_Spec', 4);
const extraBytes = ebVlr ? Las.ExtraBytes.parse(await Las.Vlr.fetch(get, ebVlr)) : [];
const data = u8.slice(header.pointDataOffset,
                      header.pointDataOffset + header.pointCount * header.pointDataRecordLength);
const view = Las.View.create(data, header, extraBytes);
// The dimensions the tests compare (all of them made the output twice as long).
const wanted = ['X', 'Y', 'Z', 'ReturnNumber', 'NumberOfReturns', 'Classification', 'UserData',
                'PointSourceId', 'GpsTime', ...extraBytes.map((e) => e.name)];
const dimensions = {};
for (const name of wanted) {
    const getter = view.getter(name);
    const values = new Array(view.pointCount);
    for (let i = 0; i < view.pointCount; ++i) values[i] = getter(i);
    dimensions[name] = values;
}
const copc = {
    points: view.pointCount,
    version: `${header.majorVersion}.${header.minorVersion}`,
    format: header.pointDataRecordFormat,
    globalEncoding: header.globalEncoding,
    fileSourceId: header.fileSourceId,
    creation: [header.fileCreationYear, header.fileCreationDayOfYear],
    scale: header.scale,
    offset: header.offset,
    min: header.min,
    max: header.max,
    vlrs: vlrs.map((v) => `${v.userId}/${v.recordId}`),
    extraBytes: extraBytes.map(({name, type, length, nodata}) => ({name, type, length, nodata})),
    dimensions,
};
process.stdout.write(JSON.stringify({loadersGl, copc}) + '\n');
