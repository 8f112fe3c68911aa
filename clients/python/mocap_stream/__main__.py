"""python -m mocap_stream HOST PORT [FRAMES]: prints the hub's live stream."""

import sys

from . import StreamClient


def main(argv=None):
    args = sys.argv[1:] if argv is None else argv
    if len(args) < 2:
        print("usage: python -m mocap_stream HOST PORT [FRAMES]", file=sys.stderr)
        return 2
    limit = int(args[2]) if len(args) > 2 else None
    count = 0
    with StreamClient(args[0], int(args[1])) as client:
        for frame in client.frames():
            print(f"frame {frame.frame_number} cameras {frame.cameras} points {len(frame.points)}")
            for p in frame.points:
                print(f"  point {p.marker} {p.provisional_track} {p.x:.3f} {p.y:.3f} {p.z:.3f}")
            count += 1
            if limit and count >= limit:
                break
    return 0 if count else 1


if __name__ == "__main__":
    sys.exit(main())
