"""The VINS-RGBD yaml of a simulated sequence, written from its config.ini, with the keys that
rawlog-convert --camera-yaml reads (libs/rgbdi_core/src/convert/vins_yaml.cpp). Used only when
rgbdi-sim did not write vins_config.yaml next to the bag itself.

VINS gives IMU noise per sample at the IMU rate; rgbdi densities convert as
acc_n = acc_noise_density / sqrt(dt / 2), acc_w = acc_random_walk / sqrt(dt) (doc/imu.md; the
inverse of imuOptionsFromVins).
"""
import configparser
import math


def read_ini(path):
    """config.ini as {section: {key: value}} with the '; comment' tails removed."""
    p = configparser.ConfigParser(inline_comment_prefixes=(";", "#"), interpolation=None)
    p.optionxform = str
    with open(path) as f:
        p.read_string(f.read(), source=path)
    return {s: dict(p.items(s)) for s in p.sections()}


def _numbers(text, count, what, path):
    v = [float(x) for x in text.split()]
    if len(v) != count:
        raise ValueError(f"{path}: {what} has {len(v)} numbers, expected {count}")
    return v


def _matrix(rows, cols, values):
    data = ", ".join(f"{x:.17g}" for x in values)
    return f"!!opencv-matrix\n   rows: {rows}\n   cols: {cols}\n   dt: d\n   data: [ {data} ]"


def vins_yaml_from_config(config_path):
    ini = read_ini(config_path)
    cam, imu, ext = ini["camera"], ini["imu"], ini["extrinsic"]
    dist = _numbers(cam.get("distortion", "0 0 0 0 0"), 5, "[camera] distortion", config_path)
    if dist[4] != 0.0:
        raise ValueError(f"{config_path}: [camera] distortion k3 = {dist[4]} cannot be "
                         "expressed in a VINS yaml (k1 k2 p1 p2 only)")
    rate = float(imu["rate_hz"])
    dt = 1.0 / rate
    R = _numbers(ext["R_body_cam"], 9, "[extrinsic] R_body_cam", config_path)
    t = _numbers(ext["t_body_cam_m"], 3, "[extrinsic] t_body_cam_m", config_path)
    lines = [
        "%YAML:1.0",
        f"# VINS-RGBD calibration written by bench/suite from {config_path}",
        "model_type: PINHOLE",
        "camera_name: camera",
        f"image_width: {int(cam['width'])}",
        f"image_height: {int(cam['height'])}",
        "distortion_parameters:",
        f"   k1: {dist[0]:.17g}",
        f"   k2: {dist[1]:.17g}",
        f"   p1: {dist[2]:.17g}",
        f"   p2: {dist[3]:.17g}",
        "projection_parameters:",
        f"   fx: {float(cam['fx']):.17g}",
        f"   fy: {float(cam['fy']):.17g}",
        f"   cx: {float(cam['cx']):.17g}",
        f"   cy: {float(cam['cy']):.17g}",
        "extrinsicRotation: " + _matrix(3, 3, R),
        "extrinsicTranslation: " + _matrix(3, 1, t),
        f"acc_n: {float(imu['acc_noise_density']) / math.sqrt(dt / 2.0):.17g}",
        f"gyr_n: {float(imu['gyr_noise_density']) / math.sqrt(dt / 2.0):.17g}",
        f"acc_w: {float(imu['acc_random_walk']) / math.sqrt(dt):.17g}",
        f"gyr_w: {float(imu['gyr_random_walk']) / math.sqrt(dt):.17g}",
        f"g_norm: {float(imu.get('gravity_m_s2', 9.81)):.17g}",
        f"td: {float(ext.get('time_offset_s', 0.0)):.17g}",
    ]
    return "\n".join(lines) + "\n"
