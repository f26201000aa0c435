#!/usr/bin/python3
"""Convert a trial of the BROAD dataset (Berlin Robust Orientation Estimation Assessment Dataset,
Laidig et al. 2021, github.com/dlaidig/broad: a myon aktos-t IMU moved by hand, Optitrack ground
truth) into the ASL layout that `rgbdi-sim --profile recorded --recording DIR` reads:

  DIR/mav0/imu0/data.csv                      t [ns], w xyz [rad/s], a xyz [m/s^2]
  DIR/mav0/imu0/sensor.yaml                   rate and noise of the IMU
  DIR/mav0/state_groundtruth_estimate0/data.csv   t [ns], p xyz [m], q w x y z
  DIR/mav0/cam0/sensor.yaml                   T_BS: a camera looking along the IMU's x axis
  DIR/conversion.txt                          what was estimated and cut, for the record

BROAD gives the optical orientation already rotated into the IMU's axes, but its position is the
marker body's origin and its clock is the motion capture's. So that the ground truth is the IMU's
own trajectory on the IMU's clock (as EuRoC's is), the script estimates from the recording itself
(printed, and written to conversion.txt):
  - the time offset: the shift of the gyroscope that best matches the optical angular rate
    (1 ms grid; a positive value means an IMU sample describes the motion of that much earlier);
  - the lever arm from the marker origin to the IMU, with an accelerometer bias: least squares
    of  a_imu - R^T (a_opt + g) = (alpha x + omega x omega x) r + b  (signals smoothed alike);
and moves the ground-truth positions to the IMU (p + R r) and the IMU stamps by the offset.
`--no-align` writes the recording as BROAD stores it.

The IMU's white noise is taken from the rest before the movement (a hand-held rest: an upper
bound); its random walks cannot be measured on minutes of data and are given by options.

Needs python3-h5py and python3-numpy (Debian packages). Example:
  scripts/broad-to-asl.py ~/broad/data_hdf5/10_undisturbed_slow_translation_A.hdf5 \
      out/recordings/broad_10 --before-move-s 3 --duration-s 60
"""
import argparse
import os
import sys

import numpy as np

GRAVITY_M_S2 = 9.81


def fail(msg):
    print(f"broad-to-asl: {msg}", file=sys.stderr)
    sys.exit(1)


def rotation_matrices(q):
    """World-from-body rotations of unit quaternions (w, x, y, z), shape (n, 3, 3)."""
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def skew(v):
    z = np.zeros(len(v))
    return np.stack([np.stack([z, -v[:, 2], v[:, 1]], -1),
                     np.stack([v[:, 2], z, -v[:, 0]], -1),
                     np.stack([-v[:, 1], v[:, 0], z], -1)], -2)


def smooth(x, k):
    ker = np.ones(k) / k
    flat = x.reshape(len(x), -1)
    out = np.stack([np.convolve(flat[:, i], ker, "same") for i in range(flat.shape[1])], 1)
    return out.reshape(x.shape)


def shifted(x, t, tau):
    """x sampled at t + tau (linear interpolation, ends held)."""
    return np.stack([np.interp(t + tau, t, x[:, i]) for i in range(x.shape[1])], 1)


def body_rates(R, dt):
    """Angular rate in the body frame at every sample: the rates of the two intervals around it
    averaged (the first and last sample take their one interval's)."""
    dR = np.einsum("nji,njk->nik", R[:-1], R[1:])
    w = np.stack([dR[:, 2, 1] - dR[:, 1, 2], dR[:, 0, 2] - dR[:, 2, 0],
                  dR[:, 1, 0] - dR[:, 0, 1]], 1) / (2 * dt)
    return np.vstack([w[:1], 0.5 * (w[:-1] + w[1:]), w[-1:]])


def estimate_alignment(t, acc, gyr, R, p, valid, smooth_samples):
    """(time offset [s], lever arm [m], accelerometer bias [m/s^2], residual rms before/after)."""
    dt = t[1] - t[0]
    w_opt = body_rates(R, dt)
    use = valid.copy()
    edge = 5 * smooth_samples
    use[:edge] = False
    use[-edge:] = False
    # Samples next to a filled gap carry interpolated optical data: leave them out.
    near_gap = np.convolve((~valid).astype(float), np.ones(2 * smooth_samples + 1), "same") > 0
    use &= ~near_gap
    gyr_s, w_s = smooth(gyr, smooth_samples), smooth(w_opt, smooth_samples)
    best = None
    for tau in np.arange(-0.030, 0.0305, 0.001):
        e = np.sqrt(((shifted(gyr_s, t, tau)[use] - w_s[use]) ** 2).mean())
        if best is None or e < best[1]:
            best = (tau, e)
    tau = float(round(best[0], 3))
    v = np.gradient(p, dt, axis=0)
    a = np.gradient(v, dt, axis=0)
    f_opt = np.einsum("nji,nj->ni", R, a + np.array([0.0, 0.0, GRAVITY_M_S2]))
    alpha = np.gradient(w_opt, dt, axis=0)
    M = skew(alpha) + np.einsum("nij,njk->nik", skew(w_opt), skew(w_opt))
    acc_s = shifted(smooth(acc, smooth_samples), t, tau)
    y = (acc_s - smooth(f_opt, smooth_samples))[use].reshape(-1)
    A = np.concatenate([smooth(M, smooth_samples)[use].reshape(-1, 3),
                        np.tile(np.eye(3), (int(use.sum()), 1))], 1)
    x, *_ = np.linalg.lstsq(A, y, rcond=None)
    rms_before = float(np.sqrt((y ** 2).mean()))
    rms_after = float(np.sqrt(((y - A @ x) ** 2).mean()))
    return tau, x[:3], x[3:], rms_before, rms_after


def write_csv(path, header, stamps_ns, values):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    tmp = path + ".tmp"
    with open(tmp, "w") as out:
        out.write(header + "\n")
        for s, row in zip(stamps_ns, values):
            out.write(str(int(s)) + "," + ",".join(f"{v:.9g}" for v in row) + "\n")
    os.replace(tmp, path)


def write_text(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    tmp = path + ".tmp"
    with open(tmp, "w") as out:
        out.write(text)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("trial", help="a BROAD trial in HDF5 (data_hdf5/NN_*.hdf5)")
    ap.add_argument("out", help="output directory (ASL layout)")
    ap.add_argument("--before-move-s", type=float, default=3.0,
                    help="seconds of the rest kept before the movement phase starts [s]")
    ap.add_argument("--duration-s", type=float, default=60.0,
                    help="length of the segment written [s] (0 = to the end)")
    ap.add_argument("--no-align", action="store_true",
                    help="keep BROAD's marker-origin positions and clocks as stored")
    ap.add_argument("--gyr-random-walk", type=float, default=1.9393e-5,
                    help="gyroscope bias random walk [rad/s^2/sqrt(Hz)] (not measurable here)")
    ap.add_argument("--acc-random-walk", type=float, default=3.0e-3,
                    help="accelerometer bias random walk [m/s^3/sqrt(Hz)] (not measurable here)")
    ap.add_argument("--smooth-samples", type=int, default=21,
                    help="moving-average length for the alignment estimate [samples]")
    args = ap.parse_args()

    try:
        import h5py
    except ImportError:
        fail("needs the Debian package python3-h5py")
    try:
        f = h5py.File(args.trial, "r")
    except OSError as e:
        fail(f"{args.trial}: cannot read as HDF5 ({e})")
    need = ["imu_acc", "imu_gyr", "opt_quat", "opt_pos", "movement"]
    missing = [k for k in need if k not in f]
    if missing or "sampling_rate" not in f.attrs:
        fail(f"{args.trial}: not a BROAD trial (missing {', '.join(missing) or 'sampling_rate'})")
    fs = float(f.attrs["sampling_rate"])
    acc, gyr = f["imu_acc"][()], f["imu_gyr"][()]
    q, p, move = f["opt_quat"][()], f["opt_pos"][()], f["movement"][()].astype(bool)
    n = len(acc)
    if not (len(gyr) == len(q) == len(p) == len(move) == n) or n < 10:
        fail(f"{args.trial}: arrays of different lengths")
    if not np.isfinite(acc).all() or not np.isfinite(gyr).all():
        fail(f"{args.trial}: non-finite IMU sample at index "
             f"{int(np.flatnonzero(~(np.isfinite(acc).all(1) & np.isfinite(gyr).all(1)))[0])}")
    if not move.any():
        fail(f"{args.trial}: no movement phase marked")
    t = np.arange(n) / fs
    valid = np.isfinite(q).all(1) & np.isfinite(p).all(1)
    qf, pf = q.copy(), p.copy()
    for arr in (qf, pf):
        for i in range(arr.shape[1]):
            arr[~valid, i] = np.interp(t[~valid], t[valid], arr[valid, i])
    qf /= np.linalg.norm(qf, axis=1)[:, None]
    R = rotation_matrices(qf)

    first_move = int(np.flatnonzero(move)[0])
    rest = slice(int(0.5 * fs), max(int(0.5 * fs) + 10, first_move - int(0.5 * fs)))
    gyr_density = float(np.sqrt((gyr[rest].std(0) ** 2).mean()) / np.sqrt(fs))
    acc_density = float(np.sqrt((acc[rest].std(0) ** 2).mean()) / np.sqrt(fs))

    tau, lever, acc_bias, rms0, rms1 = 0.0, np.zeros(3), np.zeros(3), 0.0, 0.0
    if not args.no_align:
        tau, lever, acc_bias, rms0, rms1 = estimate_alignment(t, acc, gyr, R, pf, valid,
                                                              args.smooth_samples)
    # Ground truth of the IMU: the marker origin moved by the lever arm.
    p_imu = p + np.einsum("nij,j->ni", R, lever)

    start = max(0, first_move - int(round(args.before_move_s * fs)))
    stop = n if args.duration_s <= 0 else min(n, start + int(round(args.duration_s * fs)))
    seg = slice(start, stop)
    t0_ns = 1_000_000_000  # 1 s: every stamp positive after the offset
    imu_ns = t0_ns + np.round((t[seg] - t[start] - tau) * 1e9).astype(np.int64)
    gt_ns = t0_ns + np.round((t[seg] - t[start]) * 1e9).astype(np.int64)
    keep = valid[seg]
    gaps = np.diff(gt_ns[keep]) * 1e-9
    if len(gaps) == 0:
        fail(f"{args.trial}: no ground truth in the segment")

    mav = os.path.join(args.out, "mav0")
    write_csv(os.path.join(mav, "imu0", "data.csv"),
              "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
              "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]",
              imu_ns, np.hstack([gyr[seg], acc[seg]]))
    write_csv(os.path.join(mav, "state_groundtruth_estimate0", "data.csv"),
              "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], "
              "q_RS_y [], q_RS_z []",
              gt_ns[keep], np.hstack([p_imu[seg][keep], q[seg][keep] /
                                      np.linalg.norm(q[seg][keep], axis=1)[:, None]]))
    name = os.path.splitext(os.path.basename(args.trial))[0]
    write_text(os.path.join(mav, "imu0", "sensor.yaml"),
               f"sensor_type: imu\ncomment: myon aktos-t, BROAD trial {name}\n"
               f"rate_hz: {fs:.9g}\n"
               f"gyroscope_noise_density: {gyr_density:.6g}\n"
               f"gyroscope_random_walk: {args.gyr_random_walk:.6g}\n"
               f"accelerometer_noise_density: {acc_density:.6g}\n"
               f"accelerometer_random_walk: {args.acc_random_walk:.6g}\n")
    write_text(os.path.join(mav, "cam0", "sensor.yaml"),
               "sensor_type: camera\ncomment: no camera in BROAD; rendered, looking along the "
               "IMU's x axis (camera z = IMU x, camera x = -IMU y, camera y = -IMU z)\n"
               "T_BS:\n  cols: 4\n  rows: 4\n  data: [0.0, 0.0, 1.0, 0.0,\n"
               "         -1.0, 0.0, 0.0, 0.0,\n         0.0, -1.0, 0.0, 0.0,\n"
               "         0.0, 0.0, 0.0, 1.0]\n")
    v = np.linalg.norm(np.gradient(p_imu[seg][keep], gt_ns[keep] * 1e-9, axis=0), axis=1)
    report = (f"BROAD trial: {args.trial}\n"
              f"segment: samples {start}..{stop - 1} of {n} ({(stop - start) / fs:.3f} s at "
              f"{fs:.6g} Hz), movement from {(first_move - start) / fs:.3f} s\n"
              f"ground truth: {int(keep.sum())} samples, {int((~keep).sum())} dropped (no optical "
              f"data), longest gap {gaps.max():.4f} s\n"
              f"speed [m/s]: median {np.median(v):.3f}, 95th pct {np.percentile(v, 95):.3f}\n"
              f"alignment: {'off (--no-align)' if args.no_align else 'estimated'}\n"
              f"time offset [s]: {tau:.3f} (IMU stamps moved by -{tau:.3f})\n"
              f"lever arm marker origin -> IMU [m]: {lever[0]:.4f} {lever[1]:.4f} {lever[2]:.4f}\n"
              f"accelerometer bias (fit) [m/s^2]: {acc_bias[0]:.4f} {acc_bias[1]:.4f} "
              f"{acc_bias[2]:.4f}\n"
              f"specific-force residual rms [m/s^2]: {rms0:.4f} before, {rms1:.4f} after the "
              f"lever arm\n"
              f"noise density from the rest: gyroscope {gyr_density:.4g} rad/s/sqrt(Hz), "
              f"accelerometer {acc_density:.4g} m/s^2/sqrt(Hz)\n")
    write_text(os.path.join(args.out, "conversion.txt"), report)
    print(report, end="")
    print(f"written: {args.out}")


if __name__ == "__main__":
    main()
