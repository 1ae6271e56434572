//! A plan view of one LOD frame as SVG (plain text): patches coloured by level, culled ones
//! greyed, stitched edges drawn in red, the two eye frusta as rays on the water plane.

use std::fmt::Write;

use glam::Vec3;

use super::frustum::StereoFrustum;
use super::OceanLod;

/// Colour of LOD level `l` (coarse = blue ... fine = red).
fn level_colour(l: u8) -> String {
    let hue = 230 - (l as i32 * 28).min(230);
    format!("hsl({hue},70%,60%)")
}

/// Renders the last frame of `lod` (updated with these `eyes`) seen from above, x to the
/// right and z up, covering the quadtree square plus a margin.
pub fn render(lod: &OceanLod, eyes: &StereoFrustum) -> String {
    let st = lod.settings();
    let size = st.size();
    let c = lod.grid_centre();
    let px = 1024.0 / size; // pixels per metre
    let margin = 0.06 * size;
    let (x0, z1) = (c.x - size / 2.0 - margin, c.y + size / 2.0 + margin);
    let side = (size + 2.0 * margin) * px;
    let tx = |x: f32| (x - x0) * px;
    let tz = |z: f32| (z1 - z) * px;
    let mut s = String::with_capacity(64 * 1024);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{side:.0}" height="{h:.0}" viewBox="0 0 {side:.0} {h:.0}" font-family="sans-serif" font-size="14">"#,
        h = side + 60.0
    );
    let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="#fff"/>"##);
    for (leaf, &kept) in lod.leaves().iter().zip(lod.visible()) {
        let inst = lod.instance_of(leaf);
        let h = inst.size / 2.0;
        let (l, r, b, t) = (
            inst.centre[0] - h,
            inst.centre[0] + h,
            inst.centre[1] - h,
            inst.centre[1] + h,
        );
        let fill = if kept {
            level_colour(leaf.level)
        } else {
            "#ddd".to_string()
        };
        let _ = writeln!(
            s,
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{fill}" stroke="#333" stroke-width="0.5"><title>level {} stitch {:04b}{}</title></rect>"##,
            tx(l),
            tz(t),
            inst.size * px,
            inst.size * px,
            leaf.level,
            leaf.stitch.bits(),
            if kept { "" } else { " (culled)" }
        );
        let inset = (0.06 * inst.size * px).min(3.0) / px;
        for (bit, (ax, az, bx, bz)) in [
            (1, (r - inset, b, r - inset, t)),
            (2, (l, t - inset, r, t - inset)),
            (4, (l + inset, b, l + inset, t)),
            (8, (l, b + inset, r, b + inset)),
        ] {
            if leaf.stitch.bits() & bit != 0 {
                let _ = writeln!(
                    s,
                    r##"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#d00" stroke-width="2"/>"##,
                    tx(ax),
                    tz(az),
                    tx(bx),
                    tz(bz)
                );
            }
        }
    }
    // Eye frusta: the left and right edge rays on the water plane, length S/2.
    for (eye, colour) in eyes.eyes().iter().zip(["#0a0", "#a0a"]) {
        let q = eye.orientation.normalize();
        let p = eye.position;
        for a in [eye.fov.angle_left, eye.fov.angle_right] {
            let d = q * Vec3::new(a.tan(), 0.0, -1.0);
            let flat = Vec3::new(d.x, 0.0, d.z).normalize_or_zero() * (size / 2.0);
            let _ = writeln!(
                s,
                r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="{colour}" stroke-width="2"/>"#,
                tx(p.x),
                tz(p.z),
                tx(p.x + flat.x),
                tz(p.z + flat.z)
            );
        }
        let _ = writeln!(
            s,
            r#"<circle cx="{:.2}" cy="{:.2}" r="4" fill="{colour}"/>"#,
            tx(p.x),
            tz(p.z)
        );
    }
    let stats = lod.stats();
    let _ = writeln!(
        s,
        r##"<text x="10" y="{:.0}">{} S={} m, L_max={}, ring level {}: {} patches, {} visible (grey: culled), {} draws + skirt, {} triangles.</text>
<text x="10" y="{:.0}">Colour: LOD level (blue coarse, red fine); red edges: stitched; green/magenta: left/right eye.</text>"##,
        side + 25.0,
        st.preset().name(),
        size,
        st.max_level(),
        lod.tree().ring_level(),
        stats.patches,
        stats.visible,
        stats.draws,
        stats.triangles,
        side + 47.0,
    );
    s.push_str("</svg>\n");
    s
}
