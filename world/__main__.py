"""``python -m world``: render looks, make walks, draw maps of the simulated world.

    python -m world look --pose 1.5,4,30 --out OUT        # OUT/LOOK-L.VD ... LOOK-RANGE.npy
    python -m world look --walk walk.csv --look 12 --png look.png
    python -m world walk --room 7 --looks 40 -o walk.csv  # a generated walk
    python -m world walk --bundled                         # rewrite world/data/lab-walk.csv
    python -m world map --room 7 --walk walk.csv -o map.png
    python -m world pictures --out docs/img                # the pictures in docs/world.md
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

import numpy as np


def _publish(path: Path, data: bytes) -> None:
    """Write by temporary name and rename (readers never see half a file)."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=str(path.parent))
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _pose(text: str):
    from world.pose import Pose
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"--pose wants X,Z,HEADING[,PITCH,ROLL] in ft and "
                                         f"degrees, got {text!r}") from None
    if not 3 <= len(vals) <= 5:
        raise argparse.ArgumentTypeError(f"--pose wants 3 to 5 numbers, got {len(vals)}")
    try:
        return Pose(*vals)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _room(seed):
    from world.room import bundled_lab, generate_room
    return bundled_lab() if seed is None else generate_room(seed)


def _walk_for(args, room):
    from world.walk import bundled_walk, read_walk
    if args.walk:
        return read_walk(args.walk)
    return bundled_walk() if args.room is None else None


def cmd_look(args) -> int:
    from diskfmt.layouts import encode_bi, encode_vd
    from rig.pictures import save_png
    from rig.scene import range_npy_bytes
    from world.pictures import look_strip
    from world.render import render_look
    room = _room(args.room)
    if args.pose is not None:
        pose = args.pose
    else:
        walk = _walk_for(args, room)
        if walk is None:
            from world.walk import generate_walk
            walk = generate_walk(room, args.room, args.look + 1)
        if not 0 <= args.look < len(walk):
            raise ValueError(f"--look {args.look}: the walk has looks 0..{len(walk) - 1}")
        pose = walk[args.look]
    room.check_pose(pose)
    look = render_look(room, pose, seed=args.seed, supersample=args.supersample)
    written = []
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        for name, data in ((f"{args.prefix}-L.VD", encode_vd(look.left_vd)),
                           (f"{args.prefix}-R.VD", encode_vd(look.right_vd)),
                           (f"{args.prefix}-L.BI", encode_bi(look.left_bi)),
                           (f"{args.prefix}-R.BI", encode_bi(look.right_bi)),
                           (f"{args.prefix}-RANGE.npy", range_npy_bytes(look.range_left))):
            _publish(out / name, data)
            written.append(str(out / name))
    if args.png:
        save_png(args.png, look_strip([look], per_row=1))
        written.append(args.png)
    idx, crc = look.visible_vertices()
    info = {"room": room.name, "pose": pose.as_dict(), "files": written,
            "visible_vertices": len(idx),
            "range_ft": [float(look.range_left.min()), float(look.range_left.max())]}
    print(json.dumps(info, indent=1))
    return 0


def cmd_walk(args) -> int:
    from world.walk import BUNDLED_WALK, generate_walk, make_bundled_walk, write_walk
    if args.bundled:
        p = write_walk(BUNDLED_WALK, make_bundled_walk())
        print(p)
        return 0
    if args.room is None:
        raise ValueError("walk: give --room SEED (a generated room) or --bundled")
    if not args.output:
        raise ValueError("walk: give -o FILE for the walk CSV")
    poses = generate_walk(_room(args.room), args.seed if args.seed is not None else args.room,
                          args.looks, wobble_deg=args.wobble)
    print(write_walk(args.output, poses))
    return 0


def cmd_map(args) -> int:
    from rig.pictures import save_png
    from world.odometry import OdometryNoise, dead_reckon
    from world.pictures import room_map
    room = _room(args.room)
    walk = _walk_for(args, room)
    walks = {}
    if walk:
        for i, p in enumerate(walk):
            if not room.is_free(p.x, p.z):
                raise ValueError(f"walk pose {i} ({p.x:g}, {p.z:g}) is outside the free floor "
                                 f"of {room.name}")
        walks["true walk"] = walk
        if args.dead_reckoning:
            walks["dead reckoning"] = dead_reckon(walk, OdometryNoise(seed=args.seed or 1985))
    save_png(args.output, room_map(room, walks, title=room.name))
    print(args.output)
    return 0


def cmd_pictures(args) -> int:
    """The pictures of docs/world.md."""
    from rig.pictures import save_png
    from world.odometry import OdometryNoise, dead_reckon
    from world.pictures import look_strip, room_map
    from world.render import render_look
    from world.room import bundled_lab, generate_room
    from world.walk import bundled_walk, generate_walk
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    lab, walk = bundled_lab(), bundled_walk()
    save_png(out / "world-lab-map.png",
             room_map(lab, {"true walk": walk,
                            "dead reckoning (seed 1985)": dead_reckon(walk, OdometryNoise())},
                      fov_looks=(0, 18, 30, 44), title="bundled lab and bundled walk"))
    idx = (0, 8, 18, 22, 30, 44)
    save_png(out / "world-lab-looks.png",
             look_strip([render_look(lab, walk[i], seed=1985 + i) for i in idx],
                        [f"look {i}: x {walk[i].x:.2f} z {walk[i].z:.2f} heading "
                         f"{walk[i].heading_deg:.0f}" for i in idx]))
    tiles = []
    for seed in (1, 2, 3):
        room = generate_room(seed)
        tiles.append(room_map(room, {"walk": generate_walk(room, seed, 40)}, scale=18,
                              title=f"room {seed}"))
    h = max(t.shape[0] for t in tiles)
    tiles = [np.vstack([t, np.full((h - t.shape[0], t.shape[1], 3), 255, np.uint8)]) for t in tiles]
    save_png(out / "world-rooms.png", np.hstack(tiles))
    looks = []
    for seed in (1, 2, 3):
        room = generate_room(seed)
        w = generate_walk(room, seed, 20, wobble_deg=3.0)
        looks.append(render_look(room, w[12], seed=seed))
    save_png(out / "world-room-looks.png",
             look_strip(looks, [f"room {s}, look 12 (pitch {lk.pose.pitch_deg:.1f}, roll "
                                f"{lk.pose.roll_deg:.1f})" for s, lk in zip((1, 2, 3), looks)],
                        per_row=1))
    save_png(out / "bitmaps-door.png", _door_sheet())
    for name in ("world-lab-map.png", "world-lab-looks.png", "world-rooms.png",
                 "world-room-looks.png", "bitmaps-door.png"):
        print(out / name)
    return 0


def _door_sheet():
    """docs/formats.md's picture: NSTAR's extension codes 13 and 11 on the bundled pair's door
    panel (Star at column 48, row 45, radius 40), the block map with the named fix
    --no-wrap-percent (in 1985 its 16-bit percentage wraps for a region this large, QUIRKS N6,
    and the map reads empty)."""
    from diskfmt.bitmap_files import decode_opmap, decode_rbmap
    from diskfmt.layouts import Command, decode_bi, encode_ncont
    from model.bitmaps import rotate
    from nstar.program import Nova, Options
    from rig.scene import bundled_path
    from world.pictures import bitmap_sheet
    left = decode_bi(bundled_path("LAB-L.BI").read_bytes())
    right = decode_bi(bundled_path("LAB-R.BI").read_bytes())
    nova = Nova(options=Options(bitmap_extensions=True, no_wrap_percent=True))
    nova.load_pair(left, right)
    _, maps = decode_opmap(nova.execute(encode_ncont(Command(13, 1, 48, 45, 40, 1)))[0].data)
    rm = decode_rbmap(nova.execute(encode_ncont(Command(11, 1, 48, 45, 40, 1)))[0].data)
    return bitmap_sheet(left, rm.icntr, maps, rotate(rm.irmap, -rm.orientation), rm.orientation,
                        "LAB-L.BI, the Star at the door panel (48, 45): code 13 (block map A and "
                        "B-2..B-8) and code 11 (radial map)")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m world", description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.split("\n")[2:]))
    sub = ap.add_subparsers(dest="cmd", required=True)
    lk = sub.add_parser("look", help="render one look (both cameras, .VD/.BI, true range)")
    lk.add_argument("--room", type=int, help="generated room seed (default: the bundled lab)")
    lk.add_argument("--pose", type=_pose, help="X,Z,HEADING[,PITCH,ROLL] ft and degrees")
    lk.add_argument("--walk", help="walk CSV (default: the bundled walk, or a generated one)")
    lk.add_argument("--look", type=int, default=0, help="look number in the walk (default 0)")
    lk.add_argument("--seed", type=int, default=1985, help="sensor noise seed (default 1985)")
    lk.add_argument("--supersample", type=int, default=4, choices=(1, 2, 4),
                    help="rays per pixel side (default 4, as the bundled pair)")
    lk.add_argument("--out", help="directory for PREFIX-L.VD, -R.VD, -L.BI, -R.BI, -RANGE.npy")
    lk.add_argument("--prefix", default="LOOK", help="file name prefix (default LOOK)")
    lk.add_argument("--png", help="also write a preview PNG of the .BI pair")
    lk.set_defaults(fn=cmd_look)
    wk = sub.add_parser("walk", help="write a generated walk CSV, or regenerate the bundled one")
    wk.add_argument("--room", type=int, help="generated room seed")
    wk.add_argument("--looks", type=int, default=40, help="poses (default 40)")
    wk.add_argument("--seed", type=int, help="walk seed (default: the room seed)")
    wk.add_argument("--wobble", type=float, default=0.0,
                    help="pitch and roll, uniform in +-DEG (default 0)")
    wk.add_argument("-o", "--output", help="walk CSV to write")
    wk.add_argument("--bundled", action="store_true", help="rewrite world/data/lab-walk.csv")
    wk.set_defaults(fn=cmd_walk)
    mp = sub.add_parser("map", help="draw a room from above, with a walk")
    mp.add_argument("--room", type=int, help="generated room seed (default: the bundled lab)")
    mp.add_argument("--walk", help="walk CSV (default: the bundled walk for the bundled lab)")
    mp.add_argument("--dead-reckoning", action="store_true",
                    help="also draw the dead-reckoned path")
    mp.add_argument("--seed", type=int, help="odometry noise seed (default 1985)")
    mp.add_argument("-o", "--output", required=True, help="PNG to write")
    mp.set_defaults(fn=cmd_map)
    pc = sub.add_parser("pictures", help="regenerate the pictures of docs/world.md")
    pc.add_argument("--out", default="docs/img")
    pc.set_defaults(fn=cmd_pictures)
    args = ap.parse_args(argv)
    try:
        return args.fn(args)
    except (ValueError, OSError) as e:
        print(f"python -m world {args.cmd}: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
