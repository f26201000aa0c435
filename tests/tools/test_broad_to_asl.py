#!/usr/bin/python3
"""scripts/broad-to-asl.py on synthetic BROAD trials whose answer is known: an IMU 12 mm from the
marker origin, sampled 4 ms late, moved along analytic curves. The script must find the offset
(exactly, on its 1 ms grid) and the lever arm (within 3 mm, the noise allowing), move the ground truth to the IMU,
write the ASL layout rgbdi-sim reads, and refuse damaged files with a message naming them."""
import os
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(REPO, "scripts", "broad-to-asl.py")
FS = 285.7142857142857
G = 9.81
LEVER = np.array([-0.004, 0.002, 0.012])  # marker origin -> IMU, body frame [m]
LAG_S = 0.004  # an IMU sample describes the motion this much earlier
GYR_STD, ACC_STD = 0.003, 0.05  # white noise per sample [rad/s], [m/s^2]


def quat_from_rotvec(v):
    angle = np.linalg.norm(v, axis=1)
    axis = v / np.maximum(angle, 1e-12)[:, None]
    return np.hstack([np.cos(angle / 2)[:, None], axis * np.sin(angle / 2)[:, None]])


def rot(q):
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def motion(t):
    """Marker-origin position [m] and attitude rotation vector [rad] at times t (rest until 5 s,
    then smooth sinusoids: translation up to 0.3 m, rotations up to 0.5 rad, every axis)."""
    s = np.clip((t - 5.0) / 2.0, 0.0, 1.0)
    ramp = (s * s * (3 - 2 * s))[:, None]
    p = ramp * np.stack([0.3 * np.sin(1.3 * t), 0.2 * np.sin(1.7 * t + 1), 0.1 * np.sin(2.3 * t)], 1)
    r = ramp * np.stack([0.3 * np.sin(1.1 * t), 0.2 * np.sin(1.9 * t + 0.5), 0.5 * np.sin(0.9 * t)], 1)
    return p + np.array([0.0, 0.0, 1.2]), r


def make_trial(path, seconds=40.0, nan_rows=()):
    n = int(seconds * FS)
    t = np.arange(n) / FS
    # The IMU's sample k describes the motion at t_k - LAG_S.
    h = 1e-4
    te = t - LAG_S

    def imu_point(tt):
        p, r = motion(tt)
        return p + np.einsum("nij,j->ni", rot(quat_from_rotvec(r)), LEVER), rot(quat_from_rotvec(r))

    pm, Rm = imu_point(te - h)
    p0, R0 = imu_point(te)
    pp, Rp = imu_point(te + h)
    a_world = (pp - 2 * p0 + pm) / (h * h)
    acc = np.einsum("nji,nj->ni", R0, a_world + np.array([0, 0, G]))
    dR = np.einsum("nji,njk->nik", Rm, Rp)
    gyr = np.stack([dR[:, 2, 1] - dR[:, 1, 2], dR[:, 0, 2] - dR[:, 2, 0],
                    dR[:, 1, 0] - dR[:, 0, 1]], 1) / (4 * h)
    rng = np.random.default_rng(7)
    gyr += rng.normal(0.0, GYR_STD, gyr.shape)
    acc += rng.normal(0.0, ACC_STD, acc.shape)
    p_opt, r_opt = motion(t)
    q_opt = quat_from_rotvec(r_opt)
    for i in nan_rows:
        p_opt[i] = np.nan
        q_opt[i] = np.nan
    with h5py.File(path, "w") as f:
        f.attrs["sampling_rate"] = FS
        f["imu_acc"] = acc
        f["imu_gyr"] = gyr
        f["imu_mag"] = np.zeros((n, 3))
        f["opt_pos"] = p_opt
        f["opt_quat"] = q_opt
        f["movement"] = t >= 5.0
    return t, p_opt, q_opt


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


def read_csv(path):
    return np.loadtxt(path, delimiter=",", comments="#")


class BroadToAsl(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def test_finds_the_offset_and_the_lever_arm_and_writes_the_asl_layout(self):
        trial = os.path.join(self.dir, "trial.hdf5")
        t, p_opt, q_opt = make_trial(trial, nan_rows=range(3000, 3010))
        out = os.path.join(self.dir, "out")
        res = run(trial, out, "--before-move-s", "2", "--duration-s", "20")
        self.assertEqual(res.returncode, 0, res.stderr)
        report = open(os.path.join(out, "conversion.txt")).read()
        self.assertIn("time offset [s]: 0.004 (IMU stamps moved by -0.004)", report)
        lever = [float(x) for x in
                 report.split("lever arm marker origin -> IMU [m]: ")[1].split("\n")[0].split()]
        # With the rest's noise on 40 s of this motion the fit is good to a few millimetres.
        np.testing.assert_allclose(lever, LEVER, atol=3e-3)

        mav = os.path.join(out, "mav0")
        imu = read_csv(os.path.join(mav, "imu0", "data.csv"))
        gt = read_csv(os.path.join(mav, "state_groundtruth_estimate0", "data.csv"))
        start = int(np.flatnonzero(t >= 5.0)[0]) - int(round(2 * FS))
        n = int(round(20 * FS))
        self.assertEqual(len(imu), n)
        self.assertEqual(len(gt), n - 10)  # the rows without optical data are left out
        # Stamps: the segment's first ground-truth sample at 1 s, the IMU 4 ms earlier.
        self.assertEqual(int(gt[0, 0]), 1_000_000_000)
        self.assertEqual(int(imu[0, 0]), 1_000_000_000 - 4_000_000)
        self.assertEqual(np.diff(gt[:, 0]).max(), round(11 * 1e9 / FS))  # the 10-row hole
        # The ground truth is the IMU's position: the marker's moved by R * lever arm.
        k = 100  # a sample of the segment (before the hole)
        R = rot(q_opt[start + k][None])[0]
        # (the report prints the lever arm to 0.1 mm)
        np.testing.assert_allclose(gt[k, 1:4], p_opt[start + k] + R @ np.array(lever), atol=6e-5)
        np.testing.assert_allclose(gt[k, 4:8], q_opt[start + k], atol=1e-8)
        yaml = open(os.path.join(mav, "imu0", "sensor.yaml")).read()
        self.assertIn("rate_hz: 285.714286\n", yaml)
        self.assertIn("gyroscope_random_walk: 1.9393e-05\n", yaml)
        # The white noise from the rest: density = per-sample std / sqrt(rate).
        values = dict(line.split(": ", 1) for line in yaml.splitlines())
        self.assertAlmostEqual(float(values["gyroscope_noise_density"]) / (GYR_STD / np.sqrt(FS)),
                               1.0, delta=0.05)
        self.assertAlmostEqual(float(values["accelerometer_noise_density"]) /
                               (ACC_STD / np.sqrt(FS)), 1.0, delta=0.05)
        self.assertIn("T_BS:", open(os.path.join(mav, "cam0", "sensor.yaml")).read())

    def test_no_align_keeps_the_recording_as_stored(self):
        trial = os.path.join(self.dir, "trial.hdf5")
        t, p_opt, _ = make_trial(trial, seconds=20.0)
        out = os.path.join(self.dir, "raw")
        res = run(trial, out, "--no-align", "--duration-s", "0")
        self.assertEqual(res.returncode, 0, res.stderr)
        gt = read_csv(os.path.join(out, "mav0", "state_groundtruth_estimate0", "data.csv"))
        imu = read_csv(os.path.join(out, "mav0", "imu0", "data.csv"))
        start = int(np.flatnonzero(t >= 5.0)[0]) - int(round(3 * FS))
        self.assertEqual(len(gt), len(t) - start)
        np.testing.assert_allclose(gt[:, 1:4], p_opt[start:], atol=2e-9)
        self.assertEqual(int(imu[0, 0]), int(gt[0, 0]))

    def test_damaged_input_is_refused_with_its_name(self):
        bad = os.path.join(self.dir, "bad.hdf5")
        with open(bad, "w") as f:
            f.write("not hdf5")
        res = run(bad, os.path.join(self.dir, "o1"))
        self.assertEqual(res.returncode, 1)
        self.assertIn(f"broad-to-asl: {bad}: cannot read as HDF5", res.stderr)
        partial = os.path.join(self.dir, "partial.hdf5")
        with h5py.File(partial, "w") as f:
            f["imu_acc"] = np.zeros((20, 3))
        res = run(partial, os.path.join(self.dir, "o2"))
        self.assertEqual(res.returncode, 1)
        self.assertIn(f"{partial}: not a BROAD trial (missing imu_gyr, opt_quat, opt_pos, "
                      "movement)", res.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "o2")))


if __name__ == "__main__":
    unittest.main()
