#!/usr/bin/env node
// Writes the JSON Schemas of the Foxglove message types sgslam publishes into
// foxglove/schemas/ (shipped with sgslam, read by `run --mcap`), taken from the
// official @foxglove/schemas package (viewer/package.json pins its version).
//   node scripts/foxglove_schemas.mjs          write them
//   node scripts/foxglove_schemas.mjs --check  exit 1 when a shipped file differs
import { createRequire } from "node:module";
import { readFileSync, writeFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const require = createRequire(join(root, "viewer", "package.json"));
const schemas = require("@foxglove/schemas/jsonschema");
const version = require("@foxglove/schemas/package.json").version;

export const TYPES = ["CameraCalibration", "CompressedImage", "FrameTransform", "ImageAnnotations", "PointCloud",
                      "PoseInFrame", "PosesInFrame", "SceneUpdate"];

const check = process.argv.includes("--check");
let differ = 0;
for (const type of TYPES) {
  const file = join(root, "foxglove", "schemas", `foxglove.${type}.json`);
  const text = JSON.stringify(schemas[type], null, 1) + "\n";
  if (check) {
    let shipped = "";
    try { shipped = readFileSync(file, "utf8"); } catch { /* missing: differs */ }
    if (shipped !== text) { console.error(`${file} differs from @foxglove/schemas ${version}`); differ = 1; }
  } else {
    writeFileSync(file, text);
  }
}
if (!check) {
  writeFileSync(join(root, "foxglove", "schemas", "VERSION"), `@foxglove/schemas ${version} (MIT License), exported by scripts/foxglove_schemas.mjs\n`);
  console.log(`wrote ${TYPES.length} schemas of @foxglove/schemas ${version} to foxglove/schemas/`);
}
process.exit(differ);
