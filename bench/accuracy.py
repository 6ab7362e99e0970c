"""Accuracy on real pictures, side by side (docs/accuracy.md).

The Middlebury 2014 "motorcycle" pair with its ground-truth disparity, as
scikit-image ships it (``skimage.data.stereo_motorcycle()``, 741x500, no
download), goes through PRE's import path -- ``pre.digitize.digitize`` (grey,
``--fit crop`` to 256x240, 16 levels) then ``pre.condense.condense`` to
128x120, the functions ``pre pair`` uses -- and the rig scans lines 8..112.

Ground truth at the rig's scale: the crop cuts columns ``x0 .. x0+cw-1`` of
the original (the same formulas as ``pre.digitize.fit``), so 128-px column
``c`` covers original columns ``x0 + c*cw/128 .. x0 + (c+1)*cw/128`` and row
``r`` rows ``r*ch/120 .. (r+1)*ch/120``.  A 128x120 pixel's true disparity is
the median of the valid ground truth in its footprint (valid = finite and
> 0; at least half the footprint must be valid, else the pixel is invalid),
times ``128/cw``: disparities in 128-px columns.  Both pictures are cut alike,
so the crop adds no offset to a disparity.

At a located edge (line IY, left index LOC1, array column LOC1-1 as in
rig/truth.py) the true disparity is, by default, the largest over columns
LOC1-2..LOC1 (``--halfwidth 1``): the nearest surface, the min-over-neighbours
range rule of rig/truth.py for an edge at an occluding boundary.  OpenCV's
StereoBM and StereoSGBM run on the same 4-bit pictures (level*17 on 0..255)
and are scored at those same pixels against the same truth, and over every
pixel where the truth and the matcher are both valid.

Run:  python bench/accuracy.py [--out docs/accuracy.md]
(``pip install -e .[bench]`` brings scikit-image.)
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

from pre.condense import condense                     # noqa: E402
from pre.digitize import HEIGHT, WIDTH, digitize     # noqa: E402

RIG_W, RIG_H = 128, 120
DS, DV = "0.75", "180"
DCONS = 0.75 * 180.0
LINES = range(8, 113)
BEGIN = "<!-- accuracy-table:begin -->"
END = "<!-- accuracy-table:end -->"

BM_BLOCK = 9
SGBM_BLOCK = 5
NUM_DISP = 16


# --- ground truth through PRE's crop --------------------------------------------

@dataclass(frozen=True)
class CropMap:
    """Where ``pre.digitize.fit(..., "crop")`` takes a h x w picture from, and
    what that means for a 128x120 pixel."""
    src_h: int
    src_w: int
    x0: int          # first original column kept
    y0: int          # first original row kept
    cw: int          # original columns kept
    ch: int          # original rows kept

    @property
    def col_step(self) -> float:
        """Original columns per 128-px column."""
        return self.cw / RIG_W

    @property
    def row_step(self) -> float:
        """Original rows per 120-line row."""
        return self.ch / RIG_H

    @property
    def disparity_scale(self) -> float:
        """An original disparity times this is a disparity in 128-px columns."""
        return RIG_W / self.cw


def crop_map(h: int, w: int) -> CropMap:
    """The crop of ``pre.digitize.fit`` (same formulas, same rounding)."""
    if w * HEIGHT > h * WIDTH:                    # too wide: cut the sides
        cw = max(1, round(h * WIDTH / HEIGHT))
        return CropMap(h, w, (w - cw) // 2, 0, cw, h)
    if w * HEIGHT < h * WIDTH:                    # too tall: cut top and bottom
        ch = max(1, round(w * HEIGHT / WIDTH))
        return CropMap(h, w, 0, (h - ch) // 2, w, ch)
    return CropMap(h, w, 0, 0, w, h)


def footprint(lo: float, step: float, i: int) -> tuple[int, int]:
    """Original indices [a, b) covered (even partly) by output pixel i."""
    a = lo + i * step
    b = lo + (i + 1) * step
    return int(math.floor(a + 1e-9)), int(math.ceil(b - 1e-9))


def valid_gt(d: np.ndarray) -> np.ndarray:
    """Valid ground truth: finite and > 0 (Middlebury marks unknown as inf)."""
    d = np.asarray(d, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        return np.isfinite(d) & (d > 0)


def gt_at_rig_scale(disp: np.ndarray, cmap: CropMap | None = None,
                    min_valid: float = 0.5) -> np.ndarray:
    """120x128 true disparity in 128-px columns (NaN where invalid): median of
    the valid original values in each pixel's footprint, times 128/cw."""
    disp = np.asarray(disp, dtype=np.float64)
    if disp.ndim == 3:                    # skimage may give (h, w, 1)-like maps
        disp = disp[:, :, 0]
    if cmap is None:
        cmap = crop_map(*disp.shape)
    ok = valid_gt(disp)
    out = np.full((RIG_H, RIG_W), np.nan)
    cols = [footprint(cmap.x0, cmap.col_step, c) for c in range(RIG_W)]
    for r in range(RIG_H):
        ya, yb = footprint(cmap.y0, cmap.row_step, r)
        for c, (xa, xb) in enumerate(cols):
            block_ok = ok[ya:yb, xa:xb]
            if block_ok.sum() >= min_valid * block_ok.size and block_ok.any():
                out[r, c] = np.median(disp[ya:yb, xa:xb][block_ok]) * cmap.disparity_scale
    return out


def true_disparity_at(gt: np.ndarray, line: int, col: int, halfwidth: int = 1) -> float:
    """True disparity at (line, col): the largest valid value over columns
    col-halfwidth..col+halfwidth (the nearest surface); NaN if none is valid."""
    lo, hi = max(0, col - halfwidth), min(gt.shape[1], col + halfwidth + 1)
    if not 0 <= col < gt.shape[1] or not 0 <= line < gt.shape[0]:
        return float("nan")
    win = gt[line, lo:hi]
    win = win[np.isfinite(win)]
    return float(win.max()) if win.size else float("nan")


# --- metrics ------------------------------------------------------------------

@dataclass(frozen=True)
class Metrics:
    n: int
    bad1: float          # share |err| > 1
    bad2: float          # share |err| > 2
    median_abs: float    # px


def metrics(err) -> Metrics:
    """bad-1.0, bad-2.0 and the median |error| of finite errors."""
    e = np.asarray(err, dtype=np.float64).ravel()
    e = np.abs(e[np.isfinite(e)])
    if e.size == 0:
        return Metrics(0, float("nan"), float("nan"), float("nan"))
    return Metrics(int(e.size), float(np.mean(e > 1.0)), float(np.mean(e > 2.0)),
                   float(np.median(e)))


def within_bound(dp, ep, true_disp, dcons: float = DCONS) -> np.ndarray:
    """|dp - true range| <= ep with true range = ds*dv / true disparity."""
    dp, ep, td = (np.asarray(a, dtype=np.float64) for a in (dp, ep, true_disp))
    return np.abs(dp - dcons / td) <= ep


# --- the pictures ---------------------------------------------------------------

def motorcycle():
    """(left 120x128, right 120x128, left 240x256, true disparity 120x128, crop)."""
    from skimage.data import stereo_motorcycle
    left, right, disp = stereo_motorcycle()
    # skimage gives RGB; PRE's grey step reads OpenCV's B, G, R order
    l256 = digitize(np.ascontiguousarray(left[:, :, ::-1]), "crop")
    r256 = digitize(np.ascontiguousarray(right[:, :, ::-1]), "crop")
    cmap = crop_map(*left.shape[:2])
    return condense(l256), condense(r256), l256, gt_at_rig_scale(disp, cmap), cmap


# --- the matchers ---------------------------------------------------------------

def make_bm(block: int = BM_BLOCK, num: int = NUM_DISP):
    import cv2
    return cv2.StereoBM.create(numDisparities=num, blockSize=block)


def make_sgbm(block: int = SGBM_BLOCK, num: int = NUM_DISP):
    import cv2
    return cv2.StereoSGBM.create(minDisparity=0, numDisparities=num, blockSize=block,
                                 P1=8 * block * block, P2=32 * block * block,
                                 disp12MaxDiff=1, preFilterCap=63, uniquenessRatio=10,
                                 speckleWindowSize=0, speckleRange=0,
                                 mode=cv2.StereoSGBM_MODE_HH)


def matcher_disparity(matcher, left4: np.ndarray, right4: np.ndarray) -> np.ndarray:
    """Disparity in px (NaN where the matcher gives no answer) of 4-bit pictures."""
    raw = matcher.compute((left4.astype(np.uint8) * 17), (right4.astype(np.uint8) * 17))
    d = raw.astype(np.float64) / 16.0
    d[raw < matcher.getMinDisparity() * 16] = np.nan     # invalid: (minDisparity-1)*16
    return d


# --- runs ---------------------------------------------------------------------

def scan(left, right, marf_sign_fix=False, no_wrap_percent=False):
    from diskfmt.dgreal import Real
    from estar.masl import Options as MaslOptions
    from estar.program import in_process_rig
    from nstar.program import Nova, Options as NovaOptions
    from rig.scan import run_lines
    nova = Nova(options=NovaOptions(no_wrap_percent=no_wrap_percent))
    nova.load_pair(left, right)
    ecl = in_process_rig(left, right, Real.const(DS), Real.const(DV), nova=nova,
                         options=MaslOptions(marf_sign_fix=marf_sign_fix))
    return run_lines(ecl, LINES)


def rig_columns(points) -> tuple[np.ndarray, np.ndarray]:
    from rig.truth import truth_column
    return (np.array([p.line for p in points], dtype=int),
            np.array([truth_column(p.loc1) for p in points], dtype=int))


def disp_above(points, limit: float) -> np.ndarray:
    """Located edges whose disparity exceeds ``limit`` (no surface that near)."""
    return np.array([p.disparity > limit for p in points], dtype=bool)


def median_time(fn, repeat: int) -> float:
    fn()                                                 # warm (numba, caches)
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


@dataclass
class Row:
    method: str
    where: str
    scored: str
    invalid: str
    m: Metrics
    within: str
    ms: str


def pct(x: float) -> str:
    return "-" if not np.isfinite(x) else f"{100 * x:.1f} %"


def run(halfwidth: int = 1, repeat: int = 11, threads: int = 1, num: int = NUM_DISP):
    import cv2
    cv2.setNumThreads(threads)
    left, right, _, gt, cmap = motorcycle()
    nlines = len(LINES)
    rows: list[Row] = []
    info = {"crop": cmap, "gt_valid": int(np.isfinite(gt[LINES.start:LINES.stop]).sum()),
            "gt_range": (float(np.nanmin(gt)), float(np.nanmax(gt)))}

    variants = [("rig, 1985 (default)", {}),
                ("rig + `marf_sign_fix` (E7)", {"marf_sign_fix": True}),
                ("rig + `no_wrap_percent` (N6)", {"no_wrap_percent": True})]
    base_pts = None
    for name, kw in variants:
        res = scan(left, right, **kw)
        pts = res.points
        if base_pts is None:
            base_pts = pts
            gross = disp_above(pts, info["gt_range"][1] + 1.0)
            info["gross"] = (int(gross.sum()), len(pts))
        elif kw.get("no_wrap_percent"):
            info["no_wrap_identical"] = pts == base_pts
        ys, cs = rig_columns(pts)
        td = np.array([true_disparity_at(gt, y, c, halfwidth) for y, c in zip(ys, cs)])
        disp = np.array([p.disparity for p in pts], dtype=np.float64)
        ok = np.isfinite(td)
        m = metrics(disp[ok] - td[ok])
        wb = within_bound([p.dp for p in pts], [p.ep for p in pts], td)[ok]
        t = median_time(lambda: scan(left, right, **kw), repeat)
        if not kw:
            keep = ok & ~disp_above(pts, info["gt_range"][1] + 1.0)
            info["rig_without_gross"] = metrics(disp[keep] - td[keep])
        rows.append(Row(name, f"its located edges ({len(pts) / nlines:.1f} a line)",
                        f"{m.n} of {len(pts)}", f"{len(pts) - m.n} (no truth)", m,
                        pct(float(np.mean(wb))) if wb.size else "-", f"{t * 1000:.0f}"))

    ys, cs = rig_columns(base_pts)
    td = np.array([true_disparity_at(gt, y, c, halfwidth) for y, c in zip(ys, cs)])
    ok_t = np.isfinite(td)
    band = np.zeros_like(gt, dtype=bool)
    band[LINES.start:LINES.stop] = True
    for name, matcher, settings in (
            ("OpenCV StereoBM", make_bm(num=num), f"block {BM_BLOCK}"),
            ("OpenCV StereoSGBM", make_sgbm(num=num), f"block {SGBM_BLOCK}")):
        d = matcher_disparity(matcher, left, right)
        t = median_time(lambda: matcher.compute(left * 17, right * 17), repeat)
        at = d[ys, cs]
        sel = ok_t & np.isfinite(at)
        m = metrics(at[sel] - td[sel])
        rows.append(Row(f"{name} ({settings})", "the 1985 rig's edge pixels",
                        f"{m.n} of {int(ok_t.sum())}",
                        f"{int((ok_t & ~np.isfinite(at)).sum())}", m, "-", f"{t * 1000:.2f}"))
        gv = band & np.isfinite(gt)
        sel = gv & np.isfinite(d)
        m = metrics(d[sel] - gt[sel])
        rows.append(Row(f"{name} ({settings})", "all valid pixels, lines 8..112",
                        f"{m.n} of {int(gv.sum())}", f"{int((gv & ~np.isfinite(d)).sum())}",
                        m, "-", f"{t * 1000:.2f}"))
    return rows, info


def table(rows: list[Row]) -> str:
    head = ("| method | scored at | scored | no answer / no truth | bad-1.0 | bad-2.0 | "
            "median abs error (px) | true range within ep | time per frame (ms) |")
    out = [head, "|" + "---|" * 9]
    for r in rows:
        med = "-" if not np.isfinite(r.m.median_abs) else f"{r.m.median_abs:.2f}"
        out.append(f"| {r.method} | {r.where} | {r.scored} | {r.invalid} | {pct(r.m.bad1)} | "
                   f"{pct(r.m.bad2)} | {med} | {r.within} | {r.ms} |")
    return "\n".join(out)


def settings_text(info, halfwidth: int, repeat: int, threads: int,
                  num: int = NUM_DISP) -> str:
    c = info["crop"]
    lo, hi = info["gt_range"]
    lines = [
        f"Crop: original {c.src_w}x{c.src_h}, columns {c.x0}..{c.x0 + c.cw - 1} and rows "
        f"{c.y0}..{c.y0 + c.ch - 1} kept; disparity scale 128/{c.cw} = "
        f"{c.disparity_scale:.5f}; true disparity at 128x120 {lo:.2f}..{hi:.2f} px; "
        f"{info['gt_valid']} valid pixels on lines 8..112.",
        f"Truth at an edge: largest over columns LOC1-1 +- {halfwidth}.  "
        f"StereoBM: numDisparities {num}, blockSize {BM_BLOCK}, other settings OpenCV's "
        f"defaults (prefilter XSOBEL, preFilterCap 31, textureThreshold 10, uniquenessRatio 15, "
        f"no speckle filter, no left-right check).  StereoSGBM: minDisparity 0, "
        f"numDisparities {num}, blockSize {SGBM_BLOCK}, P1 {8 * SGBM_BLOCK ** 2}, "
        f"P2 {32 * SGBM_BLOCK ** 2}, disp12MaxDiff 1, preFilterCap 63, uniquenessRatio 10, "
        f"no speckle filter, MODE_HH.  Input level*17 (0..255); outputs /16.",
        f"Time: median of {repeat} runs after a warm-up (rig: whole scans of lines 8..112 "
        f"over the direct link); OpenCV on {threads} thread(s).",
    ]
    if "gross" in info:
        g, n = info["gross"]
        w = info["rig_without_gross"]
        lines.append(f"Rig (1985) edges with a disparity above {info['gt_range'][1] + 1:.1f} px "
                     f"(nearer than anything in the picture): {g} of {n} "
                     f"({100 * g / n:.1f} %); without them (a diagnosis, not an option): "
                     f"bad-1.0 {pct(w.bad1)}, bad-2.0 {pct(w.bad2)}, median abs error "
                     f"{w.median_abs:.2f} px over {w.n} edges.")
    if "no_wrap_identical" in info:
        lines.append("no_wrap_percent scan identical to the default scan: "
                     f"{info['no_wrap_identical']}.")
    return "\n".join(lines)


def write_out(path: Path, block: str) -> None:
    """Replace the marked block in ``path`` (or write the block alone)."""
    from diskfmt.rdos import write_atomic
    text = path.read_text() if path.exists() else ""
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        tail = rest.split(END, 1)[1]
        text = head + BEGIN + "\n" + block + "\n" + END + tail
    else:
        text = BEGIN + "\n" + block + "\n" + END + "\n"
    write_atomic(path, text.encode())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        description="The rig, StereoBM and StereoSGBM on the Middlebury 2014 motorcycle "
                    "pair through PRE's import path (128x120, 16 levels, lines 8..112): "
                    "bad-1.0, bad-2.0, median error, time per frame.  Prints a Markdown table.")
    ap.add_argument("--halfwidth", type=int, default=1,
                    help="truth at an edge = largest true disparity over LOC1-1 +- this "
                         "(default 1, rig/truth.py's rule; 0 = that pixel only)")
    ap.add_argument("--repeat", type=int, default=11, help="timed runs per method (median)")
    ap.add_argument("--threads", type=int, default=1, help="OpenCV threads (default 1)")
    ap.add_argument("--num-disparities", type=int, default=NUM_DISP,
                    help=f"StereoBM/SGBM search range, a multiple of 16 (default {NUM_DISP}: "
                         "covers the true 1.9..14.4 px)")
    ap.add_argument("--out", type=Path,
                    help="also write the table into this Markdown file (between the "
                         "accuracy-table markers if it has them)")
    args = ap.parse_args(argv)
    try:
        import skimage  # noqa: F401
    except ImportError:
        print("accuracy: scikit-image is needed (pip install -e .[bench])", file=sys.stderr)
        return 1
    if args.num_disparities < 16 or args.num_disparities % 16:
        ap.error(f"--num-disparities {args.num_disparities}: a positive multiple of 16")
    rows, info = run(args.halfwidth, args.repeat, args.threads, args.num_disparities)
    cmd = "python bench/accuracy.py" + "".join(
        f" {flag} {val}" for flag, val, default in (
            ("--halfwidth", args.halfwidth, 1), ("--repeat", args.repeat, 11),
            ("--threads", args.threads, 1), ("--num-disparities", args.num_disparities, NUM_DISP))
        if val != default)
    if args.out:
        cmd += f" --out {args.out}"
    block = (table(rows) + "\n\n" + settings_text(info, args.halfwidth, args.repeat,
                                                  args.threads, args.num_disparities
                                                  ).replace("\n", "\n\n")
             + f"\n\nMade by `{cmd}`.")
    print(block)
    if args.out:
        write_out(args.out, block)
    return 0


if __name__ == "__main__":
    sys.exit(main())
