// For bench/plot_wood.sh. node plot_truth.js PLOT.ply OUT_DIR TRUTH_DIR
// PLOT.ply is a synthetic plot as `bench_plots --write` writes it (x y z as doubles, tree_id, kind:
// 1 = wood); OUT_DIR is what `treeskel plot PLOT.ply -o OUT_DIR` made of it. Each tree it found is
// matched to the true tree most of its points belong to, and that true tree's wood points are
// written to TRUTH_DIR/tree_NNN_wood.xyz (the input's frame). Prints "tree_NNN TRUE_ID WOOD_POINTS".
"use strict";
const fs = require("fs");

const kSize = { double: 8, float: 4, uint: 4, int: 4, uchar: 1 };

/// A binary little-endian PLY's vertices: { n, columns: { name: Float64Array } }.
function readPly(file) {
  const bytes = fs.readFileSync(file);
  const end = bytes.indexOf("end_header\n") + "end_header\n".length;
  const header = bytes.subarray(0, end).toString();
  if (!header.includes("format binary_little_endian")) throw new Error(file + ": not a binary little-endian PLY");
  const n = Number(/element vertex (\d+)/.exec(header)[1]);
  const props = [...header.matchAll(/property (\w+) (\w+)/g)].map((m) => ({ type: m[1], name: m[2] }));
  const stride = props.reduce((s, p) => s + kSize[p.type], 0);
  const columns = Object.fromEntries(props.map((p) => [p.name, new Float64Array(n)]));
  for (let i = 0; i < n; ++i) {
    let at = end + i * stride;
    for (const p of props) {
      const c = columns[p.name];
      if (p.type === "double") c[i] = bytes.readDoubleLE(at);
      else if (p.type === "float") c[i] = bytes.readFloatLE(at);
      else if (p.type === "uint") c[i] = bytes.readUInt32LE(at);
      else if (p.type === "int") c[i] = bytes.readInt32LE(at);
      else c[i] = bytes.readUInt8(at);
      at += kSize[p.type];
    }
  }
  return { n, columns };
}

const [plotFile, outDir, truthDir] = process.argv.slice(2);
const plot = readPly(plotFile);
const { x, y, z, tree_id: trueTree, kind } = plot.columns;
const key = (px, py, pz) => `${px},${py},${pz}`;
const truthAt = new Map();
for (let i = 0; i < plot.n; ++i) truthAt.set(key(x[i], y[i], z[i]), trueTree[i]);
fs.mkdirSync(truthDir, { recursive: true });
for (const file of fs.readdirSync(outDir + "/trees").filter((f) => /^tree_\d+\.ply$/.test(f)).sort()) {
  const tree = readPly(outDir + "/trees/" + file).columns;
  const votes = new Map();
  for (let i = 0; i < tree.x.length; ++i) {
    const t = truthAt.get(key(tree.x[i], tree.y[i], tree.z[i]));
    if (t) votes.set(t, (votes.get(t) || 0) + 1);
  }
  const best = [...votes].sort((a, b) => b[1] - a[1])[0];
  if (!best) continue;
  const lines = [];
  for (let i = 0; i < plot.n; ++i)
    if (trueTree[i] === best[0] && kind[i] === 1) lines.push(`${x[i]} ${y[i]} ${z[i]}`);
  const name = file.replace(/\.ply$/, "");
  fs.writeFileSync(`${truthDir}/${name}_wood.xyz`, lines.join("\n") + "\n");
  console.log(name, best[0], lines.length);
}
