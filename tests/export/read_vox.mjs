// Reads a MagicaVoxel .vox with npm's vox-reader (not voxbake's code) and
// prints its voxels in MagicaVoxel world coordinates as JSON for the export tests:
//   {"models": N, "voxels": [[X, Y, Z, paletteIndex], ...] (sorted), "palette": [[r,g,b,a] x 256]}
// A model's voxel (x, y, z) is at translation + (x, y, z) - floor(size / 2)
// (MagicaVoxel's convention for nTRN "_t"), following root nTRN -> nGRP -> nTRN -> nSHP.
// Usage: node read_vox.mjs FILE.vox
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";

const require = createRequire(import.meta.url);
const readVox = require("vox-reader");
const vox = readVox(readFileSync(process.argv[2]));
const list = (x) => (x === undefined ? [] : Array.isArray(x) ? x : [x]);
const sizes = list(vox.size), models = list(vox.xyzi);
const transforms = list(vox.ntrn), shapes = list(vox.nshp);
const translationOfShape = new Map();
for (const t of transforms) {
  const frame = t.frames[0] || {};
  const v = (frame._t || "0 0 0").split(" ").map(Number);
  translationOfShape.set(t.child, v);
}
const voxels = [];
shapes.forEach((s) => {
  const t = translationOfShape.get(s.nodeId) || [0, 0, 0];
  for (const [modelId] of s.models) {
    const size = sizes[modelId];
    const half = [Math.floor(size.x / 2), Math.floor(size.y / 2), Math.floor(size.z / 2)];
    for (const p of models[modelId].values)
      voxels.push([t[0] + p.x - half[0], t[1] + p.y - half[1], t[2] + p.z - half[2], p.i]);
  }
});
voxels.sort((a, b) => a[0] - b[0] || a[1] - b[1] || a[2] - b[2]);
const palette = [];
const rgba = vox.rgba.values;
for (const c of rgba) palette.push([c.r, c.g, c.b, c.a]);
console.log(JSON.stringify({ models: models.length, voxels, palette }));
