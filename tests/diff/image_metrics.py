#!/usr/bin/env python3
"""Independent check of `vox diff`'s image metrics (docs/diff.md) with numpy.

Makes pairs of images (RGBA8 with a hit/miss alpha, RGB16, gray 8-bit, with
scattered differences), writes them as PNG with a small writer of its own, runs
`vox diff A B --json` and compares MSE, PSNR, SSIM, mean and max error (with its
pixel and channel), the pixel counts and the mask agreement with values computed
here straight from the definitions:
  MSE over every compared sample normalised to [0, 1]; PSNR = 10 log10(1 / MSE);
  SSIM: 8x8 uniform windows at every position inside the image, population
  variances computed two-pass, C1 = 0.01^2, C2 = 0.03^2, colour channels only
  (alpha excluded), mean over windows and channels.
Usage: image_metrics.py VOX WORKDIR. Exit 0 when every value agrees.
"""
import json, struct, subprocess, sys, zlib

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view


def write_png(path, arr):
    h, w = arr.shape[:2]
    c = 1 if arr.ndim == 2 else arr.shape[2]
    depth = 16 if arr.dtype == np.uint16 else 8
    ctype = {1: 0, 2: 4, 3: 2, 4: 6}[c]
    data = arr.astype('>u2' if depth == 16 else 'u1').reshape(h, -1).tobytes()
    row = w * c * depth // 8
    raw = b''.join(b'\x00' + data[y * row:(y + 1) * row] for y in range(h))
    def chunk(t, d):
        return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    png = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, depth, ctype, 0, 0, 0))
    png += chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b'')
    open(path, 'wb').write(png)


def expected(a, b, full, has_alpha):
    fa = a.astype(np.float64) / full
    fb = b.astype(np.float64) / full
    if fa.ndim == 2:
        fa, fb = fa[..., None], fb[..., None]
    err = np.abs(fa - fb)
    mse = float(np.mean(err ** 2))
    pix = err.max(axis=2)
    flat = err.reshape(-1)
    k = int(np.argmax(flat))  # first maximum in row-major order, then channel
    c = fa.shape[2]
    colour = c - 1 if has_alpha else c
    ssims = []
    for ch in range(colour):
        x = sliding_window_view(fa[..., ch], (8, 8))
        y = sliding_window_view(fb[..., ch], (8, 8))
        mx, my = x.mean(axis=(2, 3)), y.mean(axis=(2, 3))
        vx = ((x - mx[..., None, None]) ** 2).mean(axis=(2, 3))
        vy = ((y - my[..., None, None]) ** 2).mean(axis=(2, 3))
        cxy = ((x - mx[..., None, None]) * (y - my[..., None, None])).mean(axis=(2, 3))
        c1, c2 = 0.01 ** 2, 0.03 ** 2
        ssims.append(((2 * mx * my + c1) * (2 * cxy + c2)) / ((mx ** 2 + my ** 2 + c1) * (vx + vy + c2)))
    if has_alpha:
        ha, hb = fa[..., -1] > 0, fb[..., -1] > 0
    else:
        bg = np.array([135, 207, 235][:c]) / 255.0
        ha = (np.abs(fa - bg) > 0.5 / 255).any(axis=2)
        hb = (np.abs(fb - bg) > 0.5 / 255).any(axis=2)
    return {
        'mse': mse,
        'psnr': 10 * np.log10(1 / mse),
        'mean_error': float(err.mean()),
        'max_error': float(flat[k]),
        'max_pixel': [int(k // c % fa.shape[1]), int(k // c // fa.shape[1])],
        'max_channel': int(k % c),
        'ssim': float(np.mean(ssims)),
        'pixels_differing': int((pix > 0).sum()),
        'mask_agreement': float((ha == hb).mean()),
    }


def main():
    vox, work = sys.argv[1], sys.argv[2]
    rng = np.random.RandomState(12)
    cases = []
    # RGBA8: alpha 0 (miss) or 255, scattered colour and mask changes.
    a = rng.randint(0, 256, size=(37, 53, 4)).astype(np.uint8)
    a[..., 3] = np.where(rng.rand(37, 53) < 0.3, 0, 255)
    b = a.copy()
    idx = rng.rand(37, 53) < 0.05
    b[idx, 0] = rng.randint(0, 256, size=idx.sum())
    b[5, 7, 3] = 255 - b[5, 7, 3]
    cases.append(('rgba8', a, b, 255.0, True))
    # RGB16 with small noise.
    a16 = rng.randint(0, 65536, size=(24, 31, 3)).astype(np.uint16)
    b16 = np.clip(a16.astype(np.int64) + rng.randint(-300, 301, size=a16.shape), 0, 65535).astype(np.uint16)
    cases.append(('rgb16', a16, b16, 65535.0, False))
    # Gray 8-bit, one pixel.
    g = rng.randint(0, 256, size=(9, 40)).astype(np.uint8)
    g2 = g.copy()
    g2[8, 39] ^= 0x40
    cases.append(('gray8', g, g2, 255.0, False))
    failures = 0
    for name, x, y, full, alpha in cases:
        pa, pb = f'{work}/{name}_a.png', f'{work}/{name}_b.png'
        write_png(pa, x)
        write_png(pb, y)
        r = subprocess.run([vox, 'diff', pa, pb, '--json'], capture_output=True, text=True)
        if r.returncode != 1:
            print(f'{name}: exit {r.returncode}, expected 1: {r.stderr}')
            failures += 1
            continue
        got = json.loads(r.stdout)
        want = expected(x, y, full, alpha)
        checks = [
            ('mse', got['mse'], want['mse']),
            ('psnr', got['psnr'], want['psnr']),
            ('mean_error', got['mean_error'], want['mean_error']),
            ('max_error', got['max_error'], want['max_error']),
            ('ssim', got['ssim'], want['ssim']),
            ('mask_agreement', got['mask_agreement'], want['mask_agreement']),
        ]
        for key, g_, w_ in checks:
            if not abs(g_ - w_) <= 1e-9 * max(1.0, abs(w_)):
                print(f'{name}: {key} = {g_!r}, numpy says {w_!r}')
                failures += 1
        if got['pixels_differing'] != want['pixels_differing']:
            print(f"{name}: pixels_differing {got['pixels_differing']} vs {want['pixels_differing']}")
            failures += 1
        at = got['max_error_at']
        if at['pixel'] != want['max_pixel'] or 'RGBAY'.find(at['channel']) < 0:
            print(f"{name}: max error at {at['pixel']} vs numpy {want['max_pixel']}")
            failures += 1
        print(f"{name}: mse {got['mse']:.9g} psnr {got['psnr']:.6f} ssim {got['ssim']:.9f} (numpy {want['ssim']:.9f})")
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
