// The water's surface seen from below (issue 45), included by `ocean.frag` after its cascade
// and lobe helpers: Snell's window (the sky and the sun refracted into the water, inside 48.6
// degrees of the normal), total internal reflection of the depths outside it, the Fresnel of
// water to air between, and the water between the surface and the eye.

// The sun's light through the surface along `t` (unit, in the air) for lobe `l`: GGX's
// distribution of the refracted directions around the sun's, per unit of its illuminance
// (1/sr), so the sun through a rough surface is a glow of the same energy. A facet tilted by
// δ turns a ray crossing from the water into the air by about (n − 1) δ near the window's
// centre, so the directions spread a third as wide as the normals: α² ninefold smaller.
const float REFRACTED_SPREAD_A2 = 0.11;
float sun_through(vec3 t, Lobe l) {
    float a2 = max(l.a2 * REFRACTED_SPREAD_A2, 1e-6);
    float c = max(dot(t, g.sun.xyz), 0.0);
    float dd = c * c * (a2 - 1.0) + 1.0;
    return g.sun.y > 0.0 ? a2 / (PI * dd * dd) : 0.0;
}

// What the eye under the water sees along unit `ray` (from the eye) of the surface at this
// fragment, `dist` m away: the surface's normal from the cascades' normal maps (explicit
// gradients `dx`, `dy` of the rest position: the pixel may be in a branch of its own at the
// waterline), its lobe widened by what the maps filtered, as above the water.
vec3 surface_from_below(vec3 ray, float dist, vec2 dx, vec2 dy) {
    int cascades = CASCADE_COUNT;
    float half_texel = g.derived.z;
    PixelCascades p;
    p.layer_slope = -interaction_at(v_xz).yz;
    UNROLL for (int c = 0; c < MAX_CASCADES; ++c) {
        if (c < cascades) {
            float inv = g.inv_patch_size[c];
            vec3 at = vec3(v_xz * inv + half_texel, float(c));
            p.c[c] = decode_cascade(textureGrad(u_normal_foam, at, dx * inv, dy * inv));
        }
    }
    Water w = water_of(p, cascades);
    float tail = g.specular_aa.x;
    Lobe l = lobe_of(sample_a2(w.smoothness, w.filtered + tail, 0.0, tail));
    // The normal on the water's side; the ray goes up into it.
    vec3 n = -w.n;
    float depth = g.underwater.y;
    mediump vec3 depths = depths_radiance(reflect(ray, n), depth);
    vec3 t = refract(ray, n, WATER_IOR);
    vec3 surface = depths;
    if (dot(t, t) > 0.0) {
        // Inside Snell's window: Schlick's Fresnel on the air's side (1 at the critical angle,
        // so the window's edge meets the reflection without a seam); the radiance gains n² on
        // entering the water (its solid angle shrinks by as much).
        mediump float cos_t = max(dot(t, -n), 0.0);
        mediump float x = 1.0 - cos_t;
        mediump float f = WATER_F0 + (1.0 - WATER_F0) * x * x * x * x * x;
        vec3 sky = sky_env(t, l.rough) + g.sun_illuminance.rgb * sun_through(t, l);
        surface = mix(sky * (WATER_IOR * WATER_IOR), depths, f);
    }
    return through_water(surface, dist, ray, depth);
}

// The colour of a pixel drawn from under the water: the surface from below for the ocean's
// fragments, the water itself where the ray meets nothing (the sky's fragments).
vec3 underwater_colour(vec3 ray, vec2 dx, vec2 dy) {
    if (v_sky != 0u) {
        return depths_radiance(ray, g.underwater.y);
    }
    return surface_from_below(ray, distance(v_world, v_eye), dx, dy);
}

// The side of the surface this ocean pixel is drawn from (issue 45): the frame's, or where the
// surface may cross a near plane (`g.underwater.x` = 2), the mesh's own: a fragment of the
// water seen from below its triangle's plane is seen from the water, and where the ray meets
// no water (the sky's fragments) it went down into the water or up into the air. Deciding by
// the drawn mesh, not by a second look at the surface, keeps the line where the mesh meets the
// near plane: the two would part by their difference (centimetres) magnified across the whole
// near plane, about 10 cm high. The meniscus: the water's fragments within a pixel and a half
// of the near plane (reversed Z: depth 1 there), i.e. where the mesh is cut by it.
// Call in uniform control flow.
Waterline ocean_waterline(vec3 ray) {
    Waterline w;
    if (frame_side(w)) {
        return w;
    }
    if (v_sky != 0u) {
        w.below = ray.y < 0.0;
    } else {
        vec3 n = cross(dFdx(v_world), dFdy(v_world));
        n = n.y < 0.0 ? -n : n;
        w.below = dot(n, v_eye - v_world) < 0.0;
        float z = gl_FragCoord.z;
        w.line = 1.0 - smoothstep(0.0, 1.5 * fwidth(z) + 1e-7, 1.0 - z);
    }
    return w;
}
