#!/usr/bin/env bash
# Relocalisation in a saved map over several seeds and the worlds where it must not relocalise
# (issue 36, doc/maps.md "Geometric relocalisation"): per case a first run maps variant 0 and
# saves its map, a second run starts in it with --load-map --localize-only; prints one markdown
# row per case: joined (by views or geometry) and when, when the online pose was first in the
# map's frame, the map-frame ATE (the run's trajectory.tum through the FIRST run's position+yaw
# alignment to ground truth only), the geometric searches and their cost, and whether the run
# stayed localised to its end. Sequences and runs are kept under OUT and reused.
#
#   scripts/reloc-acceptance.sh OUT [CASE ...]
# CASE: PROFILE:SEED (variant 1, 15 s, positive) or one of the named negative cases:
#   other_room (a world that is really another: wheeled_circle seed 7 variant 0 with
#   [sim] world_seed 7, other furniture, and room_margin_m 1.0, walls 1 m farther out, in the
#   seed-1 map), other_world (seed 7 variant 0 in the seed-1 map: the same geometry where it
#   drives; kept as information), other_furniture ([sim] world_seed 7), twin_rooms, aliased_walls (positive: must join correctly),
#   handheld41 (handheld seed 41 variant 1 30 s: must not join elsewhere).
# Default: every profile with seeds 1 2 3 and every negative case. 15 Hz throughout; maps:
# wheeled_circle --speed fast (one 26 s lap), the other profiles' default durations.
# To save disk, a mapping sequence's images and rawlog may be deleted once its map is built:
# touch OUT/NAME.mapped then keeps it from being generated again (its ground truth stays).
# Environment: DROP_MAPPED=1 deletes a mapping sequence's images and rawlog as soon as its map
# is built (and touches OUT/NAME.mapped). MAPS_ONLY=1 generates the sequences and maps of the cases and stops there (the
# second runs need the code under test; the maps do not). RUN_CONFIG=FILE runs the second runs with --config FILE, into run directories
# suffixed with TAG=... (so that one set of sequences and maps serves several configurations).
set -euo pipefail
OUT=${1:?usage: reloc-acceptance.sh OUT [CASE ...]}
shift
BIN=${BIN:-$(cd "$(dirname "$0")/.." && pwd)/build/bin}
mkdir -p "$OUT"
CASES=("$@")
if [ ${#CASES[@]} -eq 0 ]; then
  for p in wheeled_circle handheld wheeled_slopes tracked_slopes; do
    for s in 1 2 3; do CASES+=("$p:$s"); done
  done
  CASES+=(other_room other_world other_furniture twin_rooms aliased_walls handheld41)
fi

# gen NAME PROFILE SEED VARIANT DURATION [EXTRA SIM ARGS...]: a sequence under OUT/NAME.
gen() {
  local name=$1 profile=$2 seed=$3 variant=$4 duration=$5
  shift 5
  # Kept: the ground truth (the images of a mapped sequence may be deleted to save disk).
  [ -f "$OUT/$name/groundtruth.tum" ] && [ -f "$OUT/$name/sequence.rawlog" -o -f "$OUT/$name.mapped" ] && return 0
  local speed=()
  [ "$profile" = wheeled_circle ] && speed=(--speed fast)
  local dur=()
  [ "$duration" != default ] && dur=(--duration "$duration")
  "$BIN/rgbdi-sim" --profile "$profile" "${speed[@]}" --fps 15 --seed "$seed" --variant "$variant" \
    "${dur[@]}" --out "$OUT/$name" "$@" > "$OUT/$name.sim.log" 2>&1
}
TAG=${TAG:-}
RUN_ARGS=()
[ -n "${RUN_CONFIG:-}" ] && RUN_ARGS=(--config "$RUN_CONFIG")
# slam NAME SEQ [ARGS...]: a run of SEQ into OUT/NAME.
slam() {
  local name=$1 seq=$2
  shift 2
  # The second runs are those with --load-map.
  [ -n "${MAPS_ONLY:-}" ] && [[ " $* " == *" --load-map "* ]] && return 0
  [ -f "$OUT/$name/summary.json" ] && return 0
  "$BIN/rgbdi-slam" --input "$OUT/$seq/sequence.rawlog" --out "$OUT/$name" --quiet "$@" \
    > "$OUT/$name.log" 2>&1
  if [ -n "${DROP_MAPPED:-}" ] && [[ " $* " != *" --load-map "* ]]; then
    rm -rf "$OUT/$seq/sequence.rawlog" "$OUT/$seq/sequence_Images"
    touch "$OUT/$seq.mapped"
  fi
}
# row CASE MAPSEQ MAPRUN RUNSEQ RUN
row() {
  [ -n "${MAPS_ONLY:-}" ] && return 0
  python3 - "$@" <<'EOF'
import json, math, sys
case, mapseq, maprun, runseq, run = sys.argv[1:6]
out = sys.argv[6]
def tum(p):
    rows = []
    for l in open(p):
        if l.startswith('#') or not l.strip():
            continue
        rows.append([float(x) for x in l.split()])
    return rows
def yaw(q):
    qx, qy, qz, qw = q
    return math.atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz))
def nearest(tr, t):
    lo, hi = 0, len(tr) - 1
    while lo < hi:
        m = (lo + hi) // 2
        if tr[m][0] < t: lo = m + 1
        else: hi = m
    best = min((i for i in (lo - 1, lo) if 0 <= i < len(tr)), key=lambda i: abs(tr[i][0] - t))
    return tr[best]
# Position + yaw alignment of the map run to its ground truth (p_gt = R p_est + t).
gt0 = tum(f'{out}/{mapseq}/groundtruth.tum')
est0 = tum(f'{out}/{maprun}/trajectory.tum')
pairs = [(e, nearest(gt0, e[0])) for e in est0]
pairs = [(e, g) for e, g in pairs if abs(g[0] - e[0]) < 0.02]
ce = [sum(e[k] for e, _ in pairs) / len(pairs) for k in (1, 2, 3)]
cg = [sum(g[k] for _, g in pairs) / len(pairs) for k in (1, 2, 3)]
sxy = sum((e[1] - ce[0]) * (g[2] - cg[1]) - (e[2] - ce[1]) * (g[1] - cg[0]) for e, g in pairs)
sxx = sum((e[1] - ce[0]) * (g[1] - cg[0]) + (e[2] - ce[1]) * (g[2] - cg[1]) for e, g in pairs)
a = math.atan2(sxy, sxx)
c, s = math.cos(a), math.sin(a)
def to_gt(p):
    x, y, z = p[0] - ce[0], p[1] - ce[1], p[2] - ce[2]
    return (c * x - s * y + cg[0], s * x + c * y + cg[1], z + cg[2])
map_ate = math.sqrt(sum(sum((q - g[k + 1]) ** 2 for k, q in enumerate(to_gt(e[1:4]))) for e, g in pairs) / len(pairs))
summ = json.load(open(f'{out}/{run}/summary.json'))
ms = summ['map_session']
gt = tum(f'{out}/{runseq}/groundtruth.tum')
t0 = gt[0][0]
ate = '-'
worst = '-'
try:
    est = tum(f'{out}/{run}/trajectory.tum')
except Exception:
    est = []
if est:
    errs = []
    for e in est:
        g = nearest(gt, e[0])
        if abs(g[0] - e[0]) > 0.02: continue
        q = to_gt(e[1:4])
        errs.append(sum((q[k] - g[k + 1]) ** 2 for k in range(3)))
    if errs:
        ate = '%.2f' % (100 * math.sqrt(sum(errs) / len(errs)))
        worst = '%.2f' % (100 * math.sqrt(max(errs)))
joins = ms.get('joins', [])
by = joins[0]['by'] if joins else '-'
at = ms.get('relocalised_at_s')
online = ms.get('online_in_map_from_s')
g = ms.get('geometric', {})
last_t = est[-1][0] - t0 if est else None
end_t = gt[-1][0] - t0
stayed = 'yes' if est and ms.get('state') == 'localised' and last_t > end_t - 0.5 else ('-' if not joins else 'no')
fmt = lambda v: '%.2f' % v if isinstance(v, (int, float)) else 'never'
print(f"| {case} | {fmt(at)} | {by} | {fmt(online)} | {ate} | {worst} | {stayed} | "
      f"{g.get('results', 0)} ({g.get('fits', 0)} / {g.get('ambiguous', 0)} / {g.get('confirmed', 0)}) | "
      f"{g.get('ms_per_attempt_mean', 0):.0f} / {g.get('ms_per_attempt_max', 0):.0f} | {map_ate * 100:.2f} |")
EOF
}

echo "| case | joined at [s] | by | online from [s] | map-frame ATE [cm] | worst [cm] | localised to the end | searches (fits / ambiguous / confirmed) | ms per search (mean / max) | map ATE [cm] |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for c in "${CASES[@]}"; do
  case "$c" in
    other_world)
      gen wheeled_circle_v0_s1 wheeled_circle 1 0 default
      slam wheeled_circle_map_s1 wheeled_circle_v0_s1
      gen other_world_seq wheeled_circle 7 0 15
      slam other_world_run$TAG other_world_seq "${RUN_ARGS[@]}" --load-map "$OUT/wheeled_circle_map_s1/map" --localize-only
      row other_world wheeled_circle_v0_s1 wheeled_circle_map_s1 other_world_seq other_world_run$TAG "$OUT"
      ;;
    other_room)
      gen wheeled_circle_v0_s1 wheeled_circle 1 0 default
      slam wheeled_circle_map_s1 wheeled_circle_v0_s1
      printf '[sim]\nworld_seed = 7\nroom_margin_m = 1.0\n' > "$OUT/other_room.ini"
      gen other_room_seq wheeled_circle 7 0 15 --config "$OUT/other_room.ini"
      slam other_room_run$TAG other_room_seq "${RUN_ARGS[@]}" --load-map "$OUT/wheeled_circle_map_s1/map" --localize-only
      row other_room wheeled_circle_v0_s1 wheeled_circle_map_s1 other_room_seq other_room_run$TAG "$OUT"
      ;;
    other_furniture)
      gen wheeled_circle_v0_s1 wheeled_circle 1 0 default
      slam wheeled_circle_map_s1 wheeled_circle_v0_s1
      printf '[sim]\nworld_seed = 7\n' > "$OUT/world_seed7.ini"
      gen other_furniture_seq wheeled_circle 7 0 15 --config "$OUT/world_seed7.ini"
      slam other_furniture_run$TAG other_furniture_seq "${RUN_ARGS[@]}" --load-map "$OUT/wheeled_circle_map_s1/map" --localize-only
      row other_furniture wheeled_circle_v0_s1 wheeled_circle_map_s1 other_furniture_seq other_furniture_run$TAG "$OUT"
      ;;
    twin_rooms)
      printf '[sim]\ntwin_rooms = true\n' > "$OUT/twin.ini"
      gen twin_v0 wheeled_circle 1 0 default --config "$OUT/twin.ini"
      slam twin_map twin_v0
      gen twin_v1 wheeled_circle 1 1 15 --config "$OUT/twin.ini"
      slam twin_run$TAG twin_v1 "${RUN_ARGS[@]}" --load-map "$OUT/twin_map/map" --localize-only
      row twin_rooms twin_v0 twin_map twin_v1 twin_run$TAG "$OUT"
      ;;
    aliased_walls)
      gen aliased_v0 wheeled_circle 1 0 default --aliased-walls
      slam aliased_map aliased_v0
      gen aliased_v1 wheeled_circle 1 1 15 --aliased-walls
      slam aliased_run$TAG aliased_v1 "${RUN_ARGS[@]}" --load-map "$OUT/aliased_map/map" --localize-only
      row aliased_walls aliased_v0 aliased_map aliased_v1 aliased_run$TAG "$OUT"
      ;;
    handheld41)
      gen handheld_v0_s41 handheld 41 0 default
      slam handheld_map_s41 handheld_v0_s41
      gen handheld_v1_s41 handheld 41 1 30
      slam handheld41_run$TAG handheld_v1_s41 "${RUN_ARGS[@]}" --load-map "$OUT/handheld_map_s41/map" --localize-only
      row handheld41 handheld_v0_s41 handheld_map_s41 handheld_v1_s41 handheld41_run$TAG "$OUT"
      ;;
    *:*)
      p=${c%%:*}
      s=${c##*:}
      gen "${p}_v0_s$s" "$p" "$s" 0 default
      slam "${p}_map_s$s" "${p}_v0_s$s"
      gen "${p}_v1_s$s" "$p" "$s" 1 15
      slam "${p}_run_s$s$TAG" "${p}_v1_s$s" "${RUN_ARGS[@]}" --load-map "$OUT/${p}_map_s$s/map" --localize-only
      row "$p seed $s" "${p}_v0_s$s" "${p}_map_s$s" "${p}_v1_s$s" "${p}_run_s$s$TAG" "$OUT"
      ;;
    *)
      echo "unknown case $c" >&2
      exit 2
      ;;
  esac
done
