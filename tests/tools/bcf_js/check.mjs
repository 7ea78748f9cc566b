// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Test tool: reads a BCF file (a zip) with @parametricos/bcf-js, a BCF reader independent of
// bimslam, and prints what it read as JSON: the project and each topic with its viewpoints (camera,
// selected and coloured components, the snapshot's size in bytes).
// bcf-js 0.2.6 reads a 3.0 viewpoint's Coloring as 2.1's (Color/Component) and fails on the 3.0
// schema's Color/Components/Component: use it on 2.1 files.
// Usage: node check.mjs FILE.bcf 2.1|3.0   (exit 1 when bcf-js cannot read it)
import fs from "node:fs";

const [file, version] = process.argv.slice(2);
if (!file || !["2.1", "3.0"].includes(version)) {
  console.error("usage: node check.mjs FILE.bcf 2.1|3.0");
  process.exit(2);
}
// bcf-js has one entry point per version; its reader logs an error and returns when it fails.
const mod = await import(version === "2.1" ? "@parametricos/bcf-js/dist/2.1/index.js"
                                           : "@parametricos/bcf-js");
const { BcfReader } = mod.default ?? mod;
const failures = [];
const log = console.error;
console.error = (...args) => failures.push(args.map(String).join(" "));
const reader = new BcfReader();
await reader.read(fs.readFileSync(file));
console.error = log;
if (!reader.project || failures.length > 0) {
  console.error(`bcf-js could not read ${file}: ${failures.join("; ")}`);
  process.exit(1);
}
const point = (p) => (p ? [p.x, p.y, p.z] : null);
const ids = (list) => (list ?? []).map((c) => c.ifc_guid);
const topics = [];
for (const markup of reader.markups) {
  const t = markup.topic;
  const viewpoints = [];
  for (const v of markup.viewpoints) {
    const cam = v.perspective_camera;
    const png = await v.getSnapshot();
    viewpoints.push({
      guid: v.guid,
      camera: cam && {
        eye: point(cam.camera_view_point),
        direction: point(cam.camera_direction),
        up: point(cam.camera_up_vector),
        fov_deg: Number(cam.field_of_view),
      },
      selected: ids(v.components?.selection),
      colors: (v.components?.coloring ?? []).map((c) => ({ color: c.color, ids: ids(c.components) })),
      snapshot_bytes: png ? Buffer.from(png, "base64").length : 0,  // bcf-js gives base64
    });
  }
  topics.push({
    guid: t.guid,
    title: t.title,
    type: t.topic_type,
    status: t.topic_status,
    priority: t.priority,
    creation_date: t.creation_date,
    author: t.creation_author,
    description: t.description,
    viewpoints,
  });
}
console.log(JSON.stringify({ project: { id: reader.project.project_id, name: reader.project.name }, topics }));
