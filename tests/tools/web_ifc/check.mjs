// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Reads an IFC file with web-ifc (That Open Company's IFC engine, independent of IFC++) and prints
// what it found as JSON: the schema, counts per class, the meshes, vertices and triangles of all
// geometry, and their bounding box; bimslam's property sets and groups (bimslam_psets,
// bimslam_groups). Used by tests/integration/sample_building_test.cpp and
// changes_cli_test.cpp to check that another viewer opens the files bimslam writes.
//
//   node check.mjs FILE.ifc
//
// Exit codes: 0 the model opened and produced geometry without errors, 1 otherwise (the reason on
// stderr; the JSON still goes to stdout when the model opened), 2 bad usage.
import { readFileSync } from "node:fs";
import * as WebIFC from "web-ifc";

const CLASSES = [
    "IFCWALL", "IFCWALLSTANDARDCASE", "IFCDOOR", "IFCWINDOW", "IFCSLAB", "IFCCOLUMN", "IFCSTAIR",
    "IFCSTAIRFLIGHT", "IFCRAILING", "IFCFURNITURE", "IFCSPACE", "IFCOPENINGELEMENT",
    "IFCBUILDINGSTOREY", "IFCBUILDINGELEMENTPROXY", "IFCPROPERTYSET", "IFCRELDEFINESBYPROPERTIES",
    "IFCTRIANGULATEDFACESET", "IFCFACETEDBREP",
];

if (process.argv.length !== 3) {
    console.error("usage: node check.mjs FILE.ifc");
    process.exit(2);
}
const file = process.argv[2];

// web-ifc reports problems through the console: its C++ core prints "[WEB-IFC][error]..." lines
// through emscripten's stdout hook (console.log), its JavaScript side uses console.error / warn.
// Collect them as errors, and keep stdout for the JSON alone (they go to stderr).
const reported = [];
const toStderr = console.error.bind(console);
const originalLog = console.log.bind(console);
console.log = (...args) => {
    const text = args.map(String).join(" ");
    if (/^\[WEB-IFC\]\[(error|warn)/i.test(text)) {
        reported.push(text);
        toStderr(text);
    } else if (/^\[WEB-IFC\]/i.test(text)) {
        toStderr(text);
    } else {
        originalLog(...args);
    }
};
for (const level of ["error", "warn"]) {
    console[level] = (...args) => {
        reported.push(args.map(String).join(" "));
        toStderr(...args);
    };
}

let data;
try {
    data = new Uint8Array(readFileSync(file));
} catch (e) {
    console.error(`check.mjs: cannot read ${file}: ${e.message}`);
    process.exit(1);
}

const api = new WebIFC.IfcAPI();
await api.Init();
api.SetLogLevel(WebIFC.LogLevel.LOG_LEVEL_WARN);
let model = -1;
try {
    model = api.OpenModel(data, { COORDINATE_TO_ORIGIN: false });
} catch (e) {
    toStderr(`check.mjs: web-ifc could not open ${file}: ${e.message}`);
    process.exit(1);
}
if (model < 0 || !api.IsModelOpen(model)) {
    toStderr(`check.mjs: web-ifc could not open ${file}`);
    process.exit(1);
}

const out = { file, schema: api.GetModelSchema(model), counts: {} };
for (const name of CLASSES) {
    const type = api.GetTypeCodeFromName(name);
    // Without subtypes: IFCWALL does not count IFCWALLSTANDARDCASE.
    out.counts[name] = type ? api.GetLineIDsWithType(model, type, false).size() : 0;
}

// Every placed geometry of every product, transformed by its flat 4x4 (column-major) matrix.
// web-ifc applies the file's length unit (metres out) and turns the model Y-up for three.js:
// (x, y, z) of the IFC model comes out as (x, z, -y); bbox_ifc_m turns it back.
let meshes = 0, geometries = 0, vertices = 0, triangles = 0;
const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
const meshClasses = {};
api.StreamAllMeshes(model, (mesh) => {
    meshes++;
    const cls = api.GetNameFromTypeCode(api.GetLineType(model, mesh.expressID));
    meshClasses[cls] = (meshClasses[cls] || 0) + 1;
    const placed = mesh.geometries;
    for (let i = 0; i < placed.size(); i++) {
        const pg = placed.get(i);
        const geometry = api.GetGeometry(model, pg.geometryExpressID);
        // Interleaved: position xyz, normal xyz.
        const verts = api.GetVertexArray(geometry.GetVertexData(), geometry.GetVertexDataSize());
        const index = api.GetIndexArray(geometry.GetIndexData(), geometry.GetIndexDataSize());
        const m = pg.flatTransformation;
        geometries++;
        vertices += verts.length / 6;
        triangles += index.length / 3;
        for (let v = 0; v < verts.length; v += 6) {
            const x = verts[v], y = verts[v + 1], z = verts[v + 2];
            const p = [
                m[0] * x + m[4] * y + m[8] * z + m[12],
                m[1] * x + m[5] * y + m[9] * z + m[13],
                m[2] * x + m[6] * y + m[10] * z + m[14],
            ];
            for (let k = 0; k < 3; k++) {
                min[k] = Math.min(min[k], p[k]);
                max[k] = Math.max(max[k], p[k]);
            }
        }
        geometry.delete();
    }
});
out.meshes = meshes;
out.geometries = geometries;
out.vertices = vertices;
out.triangles = triangles;
out.mesh_classes = meshClasses;
if (triangles > 0) {
    const r = (v) => Math.round(v * 1e6) / 1e6;
    out.bbox = { min: min.map(r), max: max.map(r) };
    out.bbox_ifc_m = { min: [r(min[0]), r(-max[2]), r(min[1])], max: [r(max[0]), r(-min[2]), r(max[1])] };
}
// bimslam's own property sets and groups, as web-ifc reads them: each set's name, properties
// (name -> nominal value) and the GlobalIds of the objects it is on; each group's members.
const ids = (refs) => (refs || []).map((r) => api.GetLine(model, r.value).GlobalId.value);
out.bimslam_psets = [];
const rels = api.GetLineIDsWithType(model, api.GetTypeCodeFromName("IFCRELDEFINESBYPROPERTIES"));
for (let i = 0; i < rels.size(); i++) {
    const rel = api.GetLine(model, rels.get(i));
    const set = api.GetLine(model, rel.RelatingPropertyDefinition.value);
    if (!set.Name || !String(set.Name.value).startsWith("bimslam")) continue;
    const properties = {};
    for (const p of set.HasProperties || []) {
        const prop = api.GetLine(model, p.value);
        properties[prop.Name.value] = prop.NominalValue ? prop.NominalValue.value : null;
    }
    out.bimslam_psets.push({ name: set.Name.value, objects: ids(rel.RelatedObjects), properties });
}
out.bimslam_groups = [];
const assigns = api.GetLineIDsWithType(model, api.GetTypeCodeFromName("IFCRELASSIGNSTOGROUP"));
for (let i = 0; i < assigns.size(); i++) {
    const rel = api.GetLine(model, assigns.get(i));
    const group = api.GetLine(model, rel.RelatingGroup.value);
    if (!group.Name || !String(group.Name.value).startsWith("bimslam")) continue;
    out.bimslam_groups.push({ name: group.Name.value, members: ids(rel.RelatedObjects) });
}
out.error_count = reported.length;
out.errors = reported.slice(0, 50);
api.CloseModel(model);
originalLog(JSON.stringify(out, null, 2));

if (reported.length > 0) {
    toStderr(`check.mjs: web-ifc reported ${reported.length} problem(s) reading ${file}`);
    process.exit(1);
}
if (triangles === 0) {
    toStderr(`check.mjs: web-ifc produced no geometry from ${file}`);
    process.exit(1);
}
