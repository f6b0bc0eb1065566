#!/usr/bin/env python3
"""What one loop closure can make of a drifting odometry: a yardstick for issue 36's figures.

Usage: scripts/loop_closure_bound.py ODOMETRY GROUNDTRUTH [TRAJECTORY]
  (TUM format, camera-to-world: `reconstruct --odometry` writes the first, the dataset has the
  second, `reconstruct --trajectory` the third; python3-numpy, installed by install-deps.sh)

A walk that comes back to its start once tells a loop closure one thing: how far the odometry
has drifted by the return. Knowing that exactly, and nothing about where along the way the drift
came from, the best it can do for a drift that accumulates evenly is to spread the correction
along the path: frame i moves by the fraction (path length to i) / (path length to the return)
of the correction at the return (rotation about its axis, translation in proportion), frames
after the return by all of it. This prints the ATE (rigid alignment, as `vdbfuse evaluate`) of
the odometry, of that spread, and of the trajectory when one is given. A loop closure beats the
spread where the drift is uneven and it knows where (vdbfuse trusts odometry across frames its
motion prior held less: the corridor's slides), and no single-loop closure takes the ATE to a
tenth of the odometry's unless nearly all of the drift sits where it can be located.
"""
import sys

import numpy as np


def read_tum(path):
    poses = {}
    try:
        lines = open(path).read().splitlines()
    except (OSError, UnicodeDecodeError) as e:
        sys.exit(f"{path}: cannot be read ({e})")
    for number, line in enumerate(lines, 1):
        if line.startswith("#") or not line.strip():
            continue
        try:
            v = [float(x) for x in line.split()]
        except ValueError:
            v = []
        if len(v) != 8 or not np.isfinite(v).all():
            sys.exit(f"{path}:{number}: expected 8 numbers (timestamp tx ty tz qx qy qz qw), got: {line.strip()[:80]}")
        norm = np.linalg.norm(v[4:])
        if norm < 1e-9:
            sys.exit(f"{path}:{number}: the quaternion is zero")
        x, y, z, w = np.array(v[4:]) / norm
        rotation = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                             [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                             [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        pose = np.eye(4)
        pose[:3, :3] = rotation
        pose[:3, 3] = v[1:4]
        poses[round(v[0], 3)] = pose
    if not poses:
        sys.exit(f"{path}: no poses")
    return poses


def ate_cm(positions, truth):
    """RMSE after the rigid alignment (Umeyama without scale) of positions onto truth."""
    mp, mt = positions.mean(0), truth.mean(0)
    u, _, vt = np.linalg.svd((truth - mt).T @ (positions - mp))
    d = np.eye(3)
    d[2, 2] = np.sign(np.linalg.det(u @ vt))
    rotation = u @ d @ vt
    aligned = (rotation @ (positions - mp).T).T + mt
    return 100 * np.sqrt(((aligned - truth) ** 2).sum(1).mean())


def rotation_log(r):
    angle = np.arccos(np.clip((np.trace(r) - 1) / 2, -1, 1))
    if angle < 1e-12:
        return np.zeros(3)
    return angle / (2 * np.sin(angle)) * np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])


def rotation_exp(w):
    angle = np.linalg.norm(w)
    if angle < 1e-12:
        return np.eye(3)
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]) / angle
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__.split("\n\n")[1])
    odometry, truth = read_tum(sys.argv[1]), read_tum(sys.argv[2])
    stamps = sorted(t for t in odometry if t in truth)
    if len(stamps) < 3:
        sys.exit(f"{sys.argv[1]} and {sys.argv[2]} share {len(stamps)} timestamps; at least 3 needed")
    odo = [odometry[t] for t in stamps]
    gt = [truth[t] for t in stamps]
    gt_positions = np.array([g[:3, 3] for g in gt])
    # The odometry in the ground truth's frame, both starting at the first frame.
    start = gt[0] @ np.linalg.inv(odo[0])
    odo = [start @ o for o in odo]
    n = len(stamps)
    back = min(range(n // 2, n), key=lambda i: np.linalg.norm(gt_positions[i] - gt_positions[0]))
    distance = np.linalg.norm(gt_positions[back] - gt_positions[0])
    if distance > 0.3:
        sys.exit(f"the walk does not come back to its start (nearest {distance:.2f} m, at frame {back}): no loop to close")
    path = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(gt_positions, axis=0), axis=1))])
    correction = gt[back] @ np.linalg.inv(odo[back])
    axis_angle = rotation_log(correction[:3, :3])
    spread = []
    for i in range(n):
        share = min(1.0, path[i] / path[back])
        c = np.eye(4)
        c[:3, :3] = rotation_exp(share * axis_angle)
        c[:3, 3] = share * correction[:3, 3]
        spread.append((c @ odo[i])[:3, 3])
    odometry_ate = ate_cm(np.array([o[:3, 3] for o in odo]), gt_positions)
    spread_ate = ate_cm(np.array(spread), gt_positions)
    print(f"return       frame {back} of {n} ({distance * 100:.1f} cm from the start, {path[back]:.1f} m walked)")
    print(f"odometry     ATE {odometry_ate:.3f} cm")
    print(f"spread       ATE {spread_ate:.3f} cm ({spread_ate / odometry_ate:.2f} of the odometry's): the drift at the "
          "return spread along the path")
    if len(sys.argv) == 4:
        trajectory = read_tum(sys.argv[3])
        shared = [t for t in stamps if t in trajectory]
        ate = ate_cm(np.array([trajectory[t][:3, 3] for t in shared]), np.array([truth[t][:3, 3] for t in shared]))
        print(f"trajectory   ATE {ate:.3f} cm ({ate / odometry_ate:.2f} of the odometry's, {ate / spread_ate:.2f} of the spread's)")


if __name__ == "__main__":
    main()
