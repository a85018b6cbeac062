#!/usr/bin/env bash
# The main job, from a fresh Debian 12 machine: install, build, then run OracleMesh on the bundled
# bone/implant scene (Data/demo/scene.json). Writes to ./demo-output (or $1):
#   demo_mesh.vtu     the multi-material tetrahedral mesh (open in ParaView, colour by Material)
#   mesh_report.txt   its quality report (tets and volume per material, dihedral angles, features)
#   demo_dihedral.png its dihedral-angle histogram
#   demo_mesh.png     a picture of it, cut open through the screw
#   demo_oracle.vti / report.txt / demo_oracle.png   the combined oracle sampled on a grid
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$(realpath -m "${1:-$root/demo-output}")"
bash "$root/scripts/setup-debian.sh"
bash "$root/scripts/build.sh"
build="${ORACLEMESH_BUILD_DIR:-$root/build}"
site="$(ls -d "$build"/lib/python3*/site-packages | head -n 1)"
export PYTHONPATH="$site${PYTHONPATH:+:$PYTHONPATH}"
mkdir -p "$out"
/usr/bin/python3 -m oraclemesh sample "$root/Data/demo/scene.json" --dims 121 93 98 \
  -o "$out/demo_oracle.vti" --report "$out/report.txt"
/usr/bin/python3 -c "import json, oraclemesh.scene as s; print(json.dumps({str(k): v for k, v in s.load_scene('$root/Data/demo/scene.json').material_names().items()}))" > "$out/materials.json"
/usr/bin/python3 -m oraclemesh mesh "$root/Data/demo/scene.json" -o "$out/demo_mesh.vtu" \
  --report "$out/mesh_report.txt" --histogram "$out/demo_dihedral.png" 2> "$out/mesh_warnings.log"
# Both pictures under one X server, tried up to three times: a virtual X server that does not come
# up (seen once: "bad X server connection") fails pvbatch at start, not the pictures.
render_pictures() {
  xvfb-run -a -s "-screen 0 1280x1024x24" bash -c '
    pvbatch "$1/oraclemesh/render.py" "$2/demo_oracle.vti" "$2/demo_oracle.png" "$2/materials.json" &&
    pvbatch "$1/oraclemesh/render.py" "$2/demo_mesh.vtu" "$2/demo_mesh.png" "$2/materials.json"' \
    render "$site" "$out" >/dev/null 2>"$out/render.log"
}
for attempt in 1 2 3; do
  if render_pictures; then break; fi
  if [ "$attempt" = 3 ]; then echo "rendering failed, see $out/render.log" >&2; exit 1; fi
  echo "rendering failed (attempt $attempt), trying again" >&2
  sleep 2
done
echo "pictures: $out/demo_oracle.png $out/demo_mesh.png"
