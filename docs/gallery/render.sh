#!/usr/bin/env bash
# The README's gallery: six sea states and times of day and two views from the water, rendered headless at 1024x1024 per
# eye (the left eye is kept, as JPEG), each from its camera path here, with the device's default
# MSAA (4 on a GPU, 1 on lavapipe, where specular AA still keeps the far sea calm), after 12 s
# of simulated time (--settle: the whitecaps settled). On two cores of lavapipe it takes about
# two minutes. Two passes, not multiview: Mesa 22.3's lavapipe writes the second view's clipped
# triangles (the deck under the viewer) into the first view's layer.
# Usage, from anywhere: docs/gallery/render.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
cargo build --release --quiet --bin vr-ocean
bin="${CARGO_TARGET_DIR:-target}/release/vr-ocean"
frames=4
render() {
    local name=$1
    shift
    local out
    out=$(mktemp -d)
    "$bin" headless --size 1024x1024 --settle 12 --frames "$frames" --bodies 0 --format jpeg \
        --stereo two-pass \
        --path "docs/gallery/$name.path" --out "$out" "$@" >/dev/null
    cp "$out/frame_$(printf %05d $((frames - 1)))_left.jpg" "docs/gallery/$name.jpg"
    rm -rf "$out"
    echo "wrote docs/gallery/$name.jpg"
}
render calm_dawn     --wind 4  --sun-elevation 4  --sun-azimuth -100 --turbidity 3
render midday        --wind 10 --sun-elevation 60 --sun-azimuth 30   --turbidity 2.5
render fresh_low_sun --wind 14 --sun-elevation 12 --sun-azimuth -60  --turbidity 2.2
render gale          --wind 20 --sun-elevation 35 --sun-azimuth 120  --turbidity 10 --clouds 1
render broken_cloud  --wind 12 --sun-elevation 40 --sun-azimuth -150 --turbidity 2.5 --clouds 0.5
render sunset        --wind 6  --sun-elevation 1.5 --sun-azimuth -90 --turbidity 2.5 --fetch 1000
render under         --wind 5  --sun-elevation 60 --sun-azimuth -120 --turbidity 2.5
render waterline     --wind 2.5 --sun-elevation 25 --sun-azimuth -120 --turbidity 2.5
