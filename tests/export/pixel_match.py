#!/usr/bin/env python3
"""Renders an exported block mesh (.glb) in headless Chromium (WebGL2 on its
software GPU) with the block renderer's terrain shader and a metadata.json's
cameras, and compares every view with `vox render-canonical --mode
shaded,canonical` of the same scene and camera.

Per view: mask agreement (hit or sky, from the canonical image's alpha and a
second WebGL pass that draws hits white), MSE and PSNR of the shaded RGB in
[0, 1], the pixels differing by more than 2 levels and those of them that are
neither on a silhouette nor next to another voxel or face (inside a face), and the
worst pixel (is it on a silhouette, i.e. next to a pixel whose mask differs?). Passes when every view has mask agreement >= 99.9 %, PSNR >= 40
dB and MSE < 0.001 (the acceptance numbers of the block renderer's own
validation). Prints one JSON line per view; exit 1 on a failed view.

The acceptance numbers (mask agreement, MSE, PSNR, worst pixel) come from
`vox diff` of the Chromium image (written as a PNG) against the shaded render;
this script's own MSE is an independent cross-check of vox diff's, and its
masks (a WebGL pass drawing hits white, the canonical image's alpha) place the
differing pixels on silhouettes and block edges.

Usage: pixel_match.py MESH.glb METADATA.json VOX_PREFIX CHROMIUM VOX
  VOX_PREFIX: render-canonical's -o without .png (--mode shaded,canonical,normal:
  PREFIX.viewN.shaded.png, PREFIX.viewN.canonical.png, PREFIX.viewN.normal.png).
  VOX: the vox binary (for vox diff).
Only the standard library: PNGs are decoded here (8-bit, non-interlaced).
"""
import base64
import json
import math
import os
import struct
import subprocess
import sys
import tempfile
import zlib


def read_png(path):
    """(width, height, channels, rows of bytes) of an 8-bit non-interlaced PNG."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and interlace == 0, f"{path}: depth {depth}, interlace {interlace}"
            ch = {0: 1, 2: 3, 4: 2, 6: 4}[ctype]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = w * ch
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - ch] if i >= ch else 0
            b = prev[i]
            c = prev[i - ch] if i >= ch else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, ch, rows


PAGE = """<!doctype html><html><head><style>
html, body { margin: 0; background: #000; overflow: hidden; }
canvas { position: absolute; top: 0; }
</style></head><body>
<canvas id="shaded" width="%(w)d" height="%(h)d" style="left:0;width:%(w)dpx;height:%(h)dpx"></canvas>
<canvas id="mask" width="%(w)d" height="%(h)d" style="left:%(w)dpx;width:%(w)dpx;height:%(h)dpx"></canvas>
<script>
const glb = Uint8Array.from(atob("%(glb)s"), c => c.charCodeAt(0));
const view = %(view)s, proj = %(proj)s;
const dv = new DataView(glb.buffer);
const jsonLen = dv.getUint32(12, true);
const doc = JSON.parse(new TextDecoder().decode(glb.subarray(20, 20 + jsonLen)));
const bin = glb.subarray(20 + jsonLen + 8);
const VS = `#version 300 es
in vec3 position; in vec3 normal; in vec3 color;
uniform mat4 uView, uProj;
out vec3 vNormal; out vec3 vColor;
void main() { vNormal = normal; vColor = color; gl_Position = uProj * uView * vec4(position, 1.0); }`;
// terrain.wgsl, after encoding COLOR_0 (linear, glTF) back to the palette's sRGB values.
const FS = `#version 300 es
precision highp float;
in vec3 vNormal; in vec3 vColor; out vec4 outColor;
uniform bool uMask;
vec3 encode(vec3 c) {
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
void main() {
  if (uMask) { outColor = vec4(1.0); return; }
  vec3 sunDir = normalize(vec3(-0.4, -0.85, -0.5));
  vec3 sunColor = vec3(1.0, 0.97, 0.9);
  vec3 skyColor = vec3(0.53, 0.81, 0.92);
  vec3 horizonColor = vec3(0.18, 0.16, 0.12);
  vec3 n = normalize(vNormal);
  float sunDiffuse = max(dot(n, -sunDir), 0.0);
  float skyFactor = clamp(n.y * 0.5 + 0.5, 0.0, 1.0);
  vec3 ambient = (horizonColor * (1.0 - skyFactor) + skyColor * skyFactor) * 0.55;
  outColor = vec4(encode(vColor) * (ambient + sunDiffuse * sunColor), 1.0);
}`;
function draw(canvas, mask) {
  const gl = canvas.getContext("webgl2", {antialias: false, preserveDrawingBuffer: true, premultipliedAlpha: false});
  const sh = (type, src) => { const s = gl.createShader(type); gl.shaderSource(s, src); gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw gl.getShaderInfoLog(s); return s; };
  const prog = gl.createProgram();
  gl.attachShader(prog, sh(gl.VERTEX_SHADER, VS)); gl.attachShader(prog, sh(gl.FRAGMENT_SHADER, FS));
  gl.linkProgram(prog); gl.useProgram(prog);
  gl.uniformMatrix4fv(gl.getUniformLocation(prog, "uView"), false, new Float32Array(view));
  gl.uniformMatrix4fv(gl.getUniformLocation(prog, "uProj"), false, new Float32Array(proj));
  gl.uniform1i(gl.getUniformLocation(prog, "uMask"), mask ? 1 : 0);
  gl.viewport(0, 0, canvas.width, canvas.height);
  if (mask) gl.clearColor(0, 0, 0, 1); else gl.clearColor(0.53, 0.81, 0.92, 1);
  gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
  gl.enable(gl.DEPTH_TEST); gl.enable(gl.CULL_FACE); gl.cullFace(gl.BACK); gl.frontFace(gl.CCW);
  for (const mesh of doc.meshes || []) for (const p of mesh.primitives) {
    const vao = gl.createVertexArray(); gl.bindVertexArray(vao);
    for (const [name, loc] of [["POSITION", "position"], ["NORMAL", "normal"], ["COLOR_0", "color"]]) {
      const a = doc.accessors[p.attributes[name]], v = doc.bufferViews[a.bufferView];
      const buf = gl.createBuffer(); gl.bindBuffer(gl.ARRAY_BUFFER, buf);
      gl.bufferData(gl.ARRAY_BUFFER, bin.subarray(v.byteOffset, v.byteOffset + v.byteLength), gl.STATIC_DRAW);
      const l = gl.getAttribLocation(prog, loc);
      if (l < 0) continue;
      gl.enableVertexAttribArray(l);
      gl.vertexAttribPointer(l, 3, gl.FLOAT, false, v.byteStride || 12, a.byteOffset || 0);
    }
    const count = doc.accessors[p.attributes.POSITION].count;
    if (p.indices !== undefined) {
      const a = doc.accessors[p.indices], v = doc.bufferViews[a.bufferView];
      const buf = gl.createBuffer(); gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, buf);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, bin.subarray(v.byteOffset, v.byteOffset + v.byteLength), gl.STATIC_DRAW);
      gl.drawElements(gl.TRIANGLES, a.count, a.componentType, a.byteOffset || 0);
    } else {
      gl.drawArrays(gl.TRIANGLES, 0, count);
    }
  }
  gl.finish();
}
draw(document.getElementById("shaded"), false);
draw(document.getElementById("mask"), true);
</script></body></html>
"""


def write_png(path, w, h, rows):
    """An 8-bit RGB PNG of `rows` (h rows of w * 3 bytes)."""
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                           chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def vox_diff(vox, a, b):
    """vox diff's JSON for images a and b (exit 0 same, 1 differs; anything else is an error)."""
    run = subprocess.run([vox, "diff", a, b, "--json"], capture_output=True, text=True, timeout=300)
    assert run.returncode in (0, 1), f"vox diff {a} {b}: exit {run.returncode}: {run.stderr}"
    return json.loads(run.stdout)


def main():
    glb_path, meta_path, prefix, chromium, vox = sys.argv[1:6]
    meta = json.load(open(meta_path))
    w, h = meta["imageSize"]["width"], meta["imageSize"]["height"]
    glb64 = base64.b64encode(open(glb_path, "rb").read()).decode("ascii")
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for i, v in enumerate(meta["views"]):
            page = os.path.join(tmp, f"view{i}.html")
            shot = os.path.join(tmp, f"view{i}.png")
            open(page, "w").write(PAGE % {"w": w, "h": h, "glb": glb64, "view": json.dumps(v["viewMatrix"]),
                                          "proj": json.dumps(v["projectionMatrix"])})
            subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-dev-shm-usage",
                            "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist",
                            "--force-device-scale-factor=1", "--force-color-profile=srgb", "--hide-scrollbars",
                            f"--user-data-dir={os.path.join(tmp, 'profile')}", f"--window-size={2 * w},{h}",
                            "--virtual-time-budget=10000", f"--screenshot={shot}", "file://" + page],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=300)
            sw, sh_, sch, srows = read_png(shot)
            assert sw >= 2 * w and sh_ >= h, f"screenshot {sw}x{sh_}, expected {2 * w}x{h}"
            _, _, vch, vrows = read_png(f"{prefix}.view{i}.shaded.png")
            _, _, cch, crows = read_png(f"{prefix}.view{i}.canonical.png")
            assert cch == 4, "the canonical image has alpha = hit"
            agree, se, worst = 0, 0.0, (-1.0, 0, 0)
            mask_web = [[srows[y][(w + x) * sch] > 127 for x in range(w)] for y in range(h)]
            mask_vox = [[crows[y][x * 4 + 3] > 0 for x in range(w)] for y in range(h)]
            # The voxel and face each pixel shows: pixels next to another voxel or face are on an edge.
            _, _, nch, nrows = read_png(f"{prefix}.view{i}.normal.png")
            voxel = [[tuple(crows[y][x * 4:x * 4 + 3]) + tuple(nrows[y][x * nch:x * nch + 3]) for x in range(w)]
                     for y in range(h)]

            def near_edge(x, y):
                return any(0 <= x + dx < w and 0 <= y + dy < h and
                           (mask_vox[y + dy][x + dx] != mask_vox[y][x] or mask_web[y + dy][x + dx] != mask_web[y][x])
                           for dx in (-1, 0, 1) for dy in (-1, 0, 1))

            differing, off_edges = 0, []
            for y in range(h):
                for x in range(w):
                    agree += mask_web[y][x] == mask_vox[y][x]
                    d = [abs(srows[y][x * sch + c] - vrows[y][x * vch + c]) / 255.0 for c in range(3)]
                    se += sum(e * e for e in d) / 3
                    if max(d) > 2.5 / 255:
                        differing += 1
                        block_edge = any(0 <= x + dx < w and 0 <= y + dy < h and voxel[y + dy][x + dx] != voxel[y][x]
                                         for dx in (-1, 0, 1) for dy in (-1, 0, 1))
                        if not near_edge(x, y) and not block_edge:
                            off_edges.append([x, y])
                    if max(d) > worst[0]:
                        worst = (max(d), x, y)
            own_mse = se / (w * h)
            web = os.path.join(tmp, f"web{i}.png")
            write_png(web, w, h, [[srows[y][x * sch + c] for x in range(w) for c in range(3)] for y in range(h)])
            d = vox_diff(vox, web, f"{prefix}.view{i}.shaded.png")
            mse = d["mse"]
            psnr = d["psnr"] if d["psnr"] is not None else 999.0
            wx, wy = d["max_error_at"]["pixel"] if d.get("max_error_at") else (worst[1], worst[2])
            result = {"view": i, "pixels": w * h, "mask_agreement": d["mask_agreement"], "mse": mse,
                      "psnr_db": psnr, "ssim": d.get("ssim"), "hits": sum(map(sum, mask_vox)),
                      "mask_agreement_own": agree / (w * h), "mse_own": own_mse,
                      "pixels_differing": differing, "differing_inside_faces": off_edges[:20],
                      "worst_pixel": {"x": wx, "y": wy, "error": d["max_error"], "on_silhouette": near_edge(wx, wy)}}
            assert abs(own_mse - mse) <= 1e-9 + 1e-6 * mse, f"vox diff's MSE {mse} differs from this script's {own_mse}"
            ok = result["mask_agreement"] >= 0.999 and psnr >= 40 and mse < 0.001
            result["pass"] = ok
            failed += not ok
            print(json.dumps(result))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
