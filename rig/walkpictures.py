"""Pictures of a walk (``rig walk``), as BGR uint8 arrays.

* :func:`walk_map` — the room from above (x across, z up): the true walls and
  obstacle footprints, the model's vertices with their 2-sigma ellipses
  (Mahalanobis distance 2 of the x-z marginal), the true path (green), the
  robot's fused pose (blue) and dead reckoning (red).
* :func:`error_plot` — position and heading error per look, one line per
  method; refused looks are gaps.
"""

from __future__ import annotations

import cv2
import numpy as np

WHITE = (255, 255, 255)
BLACK = (0, 0, 0)
GREY = (170, 170, 170)
LIGHT = (225, 225, 225)
TRUE_C = (40, 150, 40)
EST_C = (200, 90, 20)
DR_C = (40, 40, 210)
VERTEX_C = (120, 60, 150)
METHOD_COLOURS = {"dead_reckoning": DR_C, "fused": EST_C, "a48": (0, 140, 255),
                  "rigid": (160, 160, 0), "robust": (230, 170, 90), "floor": (180, 0, 180), "kabsch": (90, 90, 90),
                  "opencv": (0, 200, 200)}


def _text(img, s, org, scale=0.5, colour=BLACK, thick=1):
    cv2.putText(img, s, org, cv2.FONT_HERSHEY_SIMPLEX, scale, colour, thick, cv2.LINE_AA)


def path_legend(result, driver: str) -> tuple[str, str, str]:
    """The map's three path labels: true, estimated (named by how the pose was
    estimated: the driving fix fused with odometry, or the joint filter), dead reckoning."""
    if getattr(result.config, "kalman", None) == "joint":
        estimated = "estimated (kalman joint: pose + features)"
    else:
        estimated = f"estimated (fused: {driver} + odometry)"
    return "true path (arrows: heading)", estimated, "dead reckoning"


def walk_map(room, result, driver: str, px_per_ft: float | None = None) -> np.ndarray:
    x0, x1, z0, z1 = room.bounds
    span = max(x1 - x0, z1 - z0)
    s = px_per_ft or 760.0 / span
    left, top, bottom = 60, 70, 150
    W = int(left * 2 + (x1 - x0) * s)
    H = int(top + bottom + (z1 - z0) * s)
    img = np.full((H, W, 3), 255, np.uint8)

    def P(x, z):
        return (int(round(left + (x - x0) * s)), int(round(top + (z1 - z) * s)))

    for ox0, ox1, oz0, oz1 in np.asarray(room.obstacles).reshape(-1, 4):
        cv2.rectangle(img, P(ox0, oz1), P(ox1, oz0), LIGHT, -1)
        cv2.rectangle(img, P(ox0, oz1), P(ox1, oz0), GREY, 1)
    cv2.rectangle(img, P(x0, z1), P(x1, z0), BLACK, 2)
    # grid every 2 ft
    for gx in np.arange(np.ceil(x0 / 2) * 2, x1 + 1e-9, 2):
        _text(img, f"{gx:g}", (P(gx, z0)[0] - 8, P(gx, z0)[1] + 18), 0.4, GREY)
    for gz in np.arange(np.ceil(z0 / 2) * 2, z1 + 1e-9, 2):
        _text(img, f"{gz:g}", (P(x0, gz)[0] - 35, P(x0, gz)[1] + 4), 0.4, GREY)
    # the model: vertices and 2-sigma ellipses of the x-z marginal (of the covariance the walk
    # reports: the consider covariance where it is kept)
    for v in result.model.vertices.values():
        c = (v.cov if v.report_cov is None else v.report_cov)[np.ix_([0, 2], [0, 2])]
        w, U = np.linalg.eigh(c)
        w = np.sqrt(np.maximum(w, 0)) * 2.0 * s
        ang = float(np.degrees(np.arctan2(-U[1, 1], U[0, 1])))   # picture rows grow downward
        ctr = P(v.mean[0], v.mean[2])
        if not (0 <= ctr[0] < W and 0 <= ctr[1] < H):
            continue
        axes = (int(min(max(w[1], 1), 4 * W)), int(min(max(w[0], 1), 4 * W)))
        # with --confirm the tentative features' ellipses are grey (they are reported apart)
        tentative = result.config.confirm is not None and not result.confirmed_by_track(v)
        cv2.ellipse(img, ctr, axes, ang, 0, 360, (205, 205, 205) if tentative else (215, 190, 230),
                    1, cv2.LINE_AA)
    for v in result.model.vertices.values():
        ctr = P(v.mean[0], v.mean[2])
        if 0 <= ctr[0] < W and 0 <= ctr[1] < H:
            cv2.circle(img, ctr, 2 if v.looks > 1 else 1, VERTEX_C, -1)
    # paths
    recs = result.records
    true_pts = [P(r.true_pose.x, r.true_pose.z) for r in recs]
    dr_pts = [P(*r.estimates["dead_reckoning"][:2]) for r in recs]
    est_pts = [P(*r.estimates["fused"][:2]) if r.estimates.get("fused") else None for r in recs]
    for pts, col in ((dr_pts, DR_C), (true_pts, TRUE_C)):
        cv2.polylines(img, [np.array(pts, np.int32)], False, col, 2, cv2.LINE_AA)
    prev = None
    for p in est_pts:
        if p is not None:
            if prev is not None:
                cv2.line(img, prev, p, EST_C, 2, cv2.LINE_AA)
            cv2.circle(img, p, 3, EST_C, -1)
        prev = p
    for r, p in zip(recs, true_pts):
        h = np.radians(r.true_pose.heading_deg)
        tip = (int(p[0] + 14 * np.sin(h)), int(p[1] - 14 * np.cos(h)))
        cv2.arrowedLine(img, p, tip, TRUE_C, 1, cv2.LINE_AA, tipLength=0.35)
    _text(img, "rig walk: the model from above (x across, z up, ft)", (left, 28), 0.6)
    if result.config.consider:
        if result.config.confirm is not None:
            n = sum(not result.confirmed_by_track(v) for v in result.model.vertices.values())
            _text(img, f"{len(result.model.vertices)} vertices ({n} tentative: grey), consider "
                       "cov. at 2 sigma (x-z)", (left, 52), 0.45)
        else:
            _text(img, f"{len(result.model.vertices)} vertices, consider covariance at 2 sigma "
                       "(x-z); grey: the room", (left, 52), 0.45)
    else:
        _text(img, f"{len(result.model.vertices)} vertices, ellipses at 2 sigma (x-z); "
                   f"grey: true walls and obstacles", (left, 52), 0.45)
    y = H - bottom + 40
    for label, col in zip(path_legend(result, driver), (TRUE_C, EST_C, DR_C)):
        cv2.line(img, (left, y - 5), (left + 30, y - 5), col, 3)
        _text(img, label, (left + 40, y), 0.5)
        y += 24
    cv2.circle(img, (left + 15, y - 5), 3, VERTEX_C, -1)
    _text(img, "model vertex (larger: seen in more than one look)", (left + 40, y), 0.5)
    return img


def error_plot(result, methods=None, max_pos: float = 2.0, max_head: float = 10.0) -> np.ndarray:
    recs = result.records
    names = methods or [m for m in METHOD_COLOURS if m in recs[0].estimates]
    W, ph, left, top, gap = 900, 260, 70, 50, 70
    H = top + 2 * ph + gap + 50 + 22 * ((len(names) + 3) // 4)
    img = np.full((H, W, 3), 255, np.uint8)
    n = max(len(recs) - 1, 1)
    pw = W - left - 30

    def X(k):
        return int(left + k * pw / n)

    panels = ((0, "position error, ft", max_pos, top), (1, "heading error, deg", max_head, top + ph + gap))
    for idx, title, vmax, y0 in panels:
        cv2.rectangle(img, (left, y0), (left + pw, y0 + ph), BLACK, 1)
        _text(img, f"{title} (clipped at {vmax:g})", (left, y0 - 10), 0.5)
        for frac in (0.25, 0.5, 0.75):
            yy = int(y0 + ph - frac * ph)
            cv2.line(img, (left, yy), (left + pw, yy), LIGHT, 1)
            _text(img, f"{frac * vmax:g}", (8, yy + 4), 0.4, GREY)
        for k in range(0, len(recs), max(1, len(recs) // 10)):
            _text(img, str(k), (X(k) - 5, y0 + ph + 16), 0.4, GREY)
        for m in names:
            col = METHOD_COLOURS.get(m, BLACK)
            prev = None
            for k, r in enumerate(recs):
                e = r.errors(m)
                if e is None:
                    prev = None
                    continue
                p = (X(k), int(y0 + ph - min(e[idx], vmax) / vmax * ph))
                if prev is not None:
                    cv2.line(img, prev, p, col, 2 if m in ("fused", "dead_reckoning") else 1,
                             cv2.LINE_AA)
                prev = p
    _text(img, "look", (left + pw // 2, top + 2 * ph + gap + 34), 0.45)
    y = top + 2 * ph + gap + 56
    for i, m in enumerate(names):
        x = left + (i % 4) * 200
        yy = y + 22 * (i // 4)
        cv2.line(img, (x, yy - 5), (x + 30, yy - 5), METHOD_COLOURS.get(m, BLACK), 3)
        _text(img, m, (x + 38, yy), 0.5)
    return img
