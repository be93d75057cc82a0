/* final_gather.c - the final gather: one more bounce of light computed per pixel, on top of the
 * radiosity solution.
 *
 * At the first diffuse point x a camera path reaches (normal n, reflectance rho, emitted
 * radiance L_e) the radiance leaving towards the camera is
 *
 *     L(x) = L_e(x) + rho / pi * E_direct(x) + rho * mean_i L_reflected(y_i)
 *
 *   E_direct   irradiance straight from the emitters, estimated by sampling points y on the
 *              emitting elements by power and area, with a shadow ray each:
 *              L_e(y) cos_x cos_y / |x - y|^2 / pdf_area(y).
 *   y_i        the hits of N rays leaving x with density cos / pi; what they see is taken from
 *              the radiosity solution, but only its reflected part (B - E) / pi, because the
 *              light coming straight from the emitters is estimated by the emitter samples.
 *              Rays that pass through mirrors or glass first take (B - E) / pi too
 *              (second_pass.c): the light of an emitter by way of a mirror or glass is the
 *              specular-first pass's (docs/specular-first.md), emitted by the element it landed
 *              on and sampled there like any emitter.
 *
 * The emitted light is estimated twice, by the emitter samples and by the gather rays that hit
 * an emitter, and the two are combined with the power heuristic of multiple importance sampling
 * (Veach & Guibas 1995): each sample's emitted contribution is weighted by
 * (n_s p_s)^2 / sum_t (n_t p_t)^2 over both strategies. Emitter sampling alone has unbounded
 * variance where a receiver nearly touches an emitter (1 / distance^2); the gather rays are
 * good exactly there.
 *
 * The solution is thus only seen one bounce away, where its flaws (light leaking under walls,
 * blocky shadows of coarse elements, the smoothing of interpolation) are blurred by the
 * integral over the hemisphere, and direct light, the sharpest part, is exact up to noise.
 * After Reichert 1992 (MSc thesis, "A two-pass radiosity method driven by lights and viewer
 * position") and Lischinski, Tampieri & Greenberg 1993 ("Combining hierarchical radiosity and
 * discontinuity meshing"), who render the solution this way; photon mapping reuses the idea
 * (Jensen 1996, "Global illumination using photon maps").
 *
 * Both point sets are stratified over the whole pixel: with S camera samples in the pixel and n
 * rays per sample, ray i of sample s is point s n + i of the pixel's S n Owen-scrambled Sobol'
 * points in its own dimension (core/sampler.h; Burley 2020): each sample's n points are an
 * aligned run, so they are stratified for the sample and the pixel's S n points for the pixel
 * (one (0,m,2)-net each when the counts are powers of two), and blocks of pixels in Morton
 * order are stratified together (Ahmed & Wonka 2020). A few rays per sample then cover the
 * hemisphere and the light evenly across the pixel. */
#include "render/render.h"

#include <stdatomic.h>

/* Short gather rays (below): nearer than SHORT_RANGE element sizes of what they hit, or
 * DARK_SHORT_RANGE from a dark receiver, at most SHORT_LEVELS times along a path. */
#define SHORT_RANGE 4.0
#define DARK_SHORT_RANGE 8.0
/* Two levels, the second only for the re-gathers' rays nearer than NEAR_RANGE element sizes (a
 * contact) on a uniform mesh. With one level the re-gather's own gather rays read the solution
 * even when short, and where the short block's front face stands on the floor the row of pixels
 * at the contact was 6.8 % too bright (x 124-147, y 235, the mean of seeds 0-9; the rows above and
 * below +2.1 / +2.8 %): rays from the face's foot read the floor element beside it, which holds
 * its mean over an element, brighter than the contact. Gathered again within half an element:
 * +1.0 % (-1.2 / -0.5 %), Cornell 256 seeds 0-9 4x4 0.697 -> 0.691 %, 8x8 0.453 -> 0.449 %, gather
 * rays +3.3 %, shadow +5.8 % (cornell51, docs/rendering.md). Within 1 or 4 element sizes (the
 * second level as the first, corn4's two levels): the same errors for +5.6 / +18 % gather rays.
 * (corn4 measured two full levels at 5 % more gather rays for no gain over seeds 0-5, before
 * the re-gathers traced two rays; the contact row was not looked at.) */
#define SHORT_LEVELS 2
#define NEAR_RANGE 0.5
/* Beyond EVEN_RANGE element sizes, short rays are gathered again only onto elements where the
 * light varies inside the element: within NEAR_SURFACE element sizes of another surface (a
 * concave corner or a contact, where the indirect light falls towards the junction: found by
 * NEAR_PROBES rays from the centroid, NEAR_ELEVATION above its plane), or lit unevenly by the
 * emitters (a shadow's edge crosses it: penumbra.c, its centroid and corners against points of
 * the lamps). Elsewhere the solution varies over an element as smoothly as its corners, and
 * the short ray reads it as a far one does. Each element is tested once, when a short ray first
 * meets it. Cornell 256 x 256, seeds 0-3 against the 16k-path image: 4x4 RMSE 0.663 -> 0.650 %,
 * 8x8 0.430 -> 0.422 %, 16x16 0.268 -> 0.265 % (fewer re-gathers, less of their noise), gather
 * rays 6.84 -> 6.22 M, shadow 1.80 -> 1.62 M; the generated house (128 x 96 against 8192 paths,
 * seeds 0-2) 8x8 0.16-0.18 -> 0.17-0.19 %, gather rays 1.50 -> 1.27 M (docs/rendering.md,
 * "Re-gathers where the light varies"). Without the corner test the house's upper corners were 1 % bright in 8x8
 * blocks; every short ray onto a smooth element read from the solution (EVEN_RANGE 0) made the
 * Cornell box's contact rows 5-6 % bright. */
#define EVEN_RANGE 0.5
#define NEAR_SURFACE 1.0
#define NEAR_PROBES 8
#define NEAR_ELEVATION 0.2617993877991494 /* 15 degrees */
/* On a coarse hierarchy's leaves (RAD_LEAVES_COARSE) every first gather ray is re-gathered, and
 * the re-gathers' own rays are re-gathered again when short (SHORT_RANGE), up to this many
 * levels. The leaves at a concave contact are large and hold their mean, brighter than the
 * contact: a re-gather's ray from the floor beside the short block's base read the face's
 * leaf (its mean over 80 mm or more) and made the base's 8x8 blocks +15% bright, the back
 * corner's +17% (Cornell 256, docs/hierarchical.md "Contacts read through the re-gather"). */
#define COARSE_SHORT_LEVELS 3
/* On a finely refined hierarchy's leaves (RAD_LEAVES_FINE, link error 1e-5 or less) gather rays
 * are read where they land, as on a uniform mesh, but short ones are gathered again two levels
 * deep: the leaves at the dark contacts (the short block's face, the back corner) are still
 * larger there than a uniform mesh's elements, the threshold being absolute. Cornell 256 x 256
 * at link error 1e-5, seeds 1-4: 4x4 RMSE 0.99-1.01 % with one level, 0.93-0.94 % with two, the
 * worst 8x8 block 4.7-5.2 % off against 2.7-4.3 %, for 9 % more gather and 17 % more shadow
 * rays (docs/hierarchical.md, "The Cornell render from fine leaves"). Three levels since the
 * links read their sources by the kernel (RAD_HIER_FINE_SOURCE_DEPTH), at link error 5e-6,
 * seeds 0-3: 8x8 RMSE 0.419-0.451 -> 0.407-0.438 % (bias 0.238 -> 0.218 %, the short block's
 * face above the floor), 16x16 0.255-0.302 -> 0.246-0.292 %, gather rays +5.5 %, shadow
 * +10.6 % (docs/hierarchical.md, "hcornell2"). */
#define FINE_SHORT_LEVELS 3
/* Gather rays of the second and third re-gathers on fine leaves (the first keeps SHORT_RAYS):
 * two at each level multiplied the deep chains' rays for little of the noise: the hierarchical
 * Cornell render 7 % less processor time, 4x4 error 0.659 -> 0.666 % (docs/hierarchical.md,
 * "Sixteenth session"). */
#define FINE_DEEP_RAYS 1
/* Gather rays of a re-gather (below) on a uniform mesh. Its one emitter sample is not what is
 * noisy: its gather ray is, and it made about a sixth of the Cornell box's 4x4 noise variance
 * (cornell50: 256 x 256, seeds 0-3, gather rays 5.69 -> 6.45 M for 2, processor +8 %; 4x4 RMSE
 * 0.77 -> 0.71 %, 8x8 0.50 -> 0.47 %, 16x16 0.33 -> 0.30 %; 4 rays: 7.97 M, 0.70 / 0.46 / 0.30 %;
 * 8 emitter samples instead: 4x4 0.77 -> 0.73 %). A coarse hierarchy's re-gathers (every first
 * gather ray, up to COARSE_SHORT_LEVELS deep) keep one past the first level (COARSE_FIRST_RAYS):
 * two would multiply at each level. */
#define SHORT_RAYS 2
/* Gather rays of a first gather ray's re-gather on a coarse hierarchy's leaves (every first
 * gather ray is re-gathered there; deeper re-gathers keep one ray). That chain, not the pixel's
 * own emitter samples, made most of Sponza's block noise (docs/hierarchical.md, "sponza3"):
 * with 2, Sponza seeds 0-5's worst 16x16 blocks went from -5.0..+3.3 % to -4.6..+2.1 % for 5 %
 * more processor time (docs/hierarchical.md, "Lead, fourteenth session"). */
#define COARSE_FIRST_RAYS 2

/* ------------------------------------------------------------------------------------------- */
/* Direct light                                                                                 */

/* The emitter table's entry for the point `hit` is on; -1 when it does not emit. */
static int32_t hit_emitter(const rad_renderer *r, const rad_element_hit *hit) {
    if (r->emitters.count == 0) return -1;
    /* Embree's split of a quad: (v0, v1, v3) below the diagonal u + v = 1, (v2, v3, v1) above. */
    int piece = rad_mesh_corner_count(r->mesh, hit->element) == 4 && hit->u + hit->v > 1;
    return r->element_emitter[hit->element][piece];
}

double rad_emitter_pdf(const rad_renderer *r, rad_vec3 origin, rad_vec3 normal, rad_vec3 direction,
                       const rad_element_hit *hit) {
    int32_t k = hit_emitter(r, hit);
    if (k < 0) return 0;
    return rad_emitter_table_pdf(&r->emitters, (size_t)k, origin, normal, direction, hit->t);
}

/* rad_emitter_pdf from the point's emitter choice. */
static double choice_hit_pdf(const rad_renderer *r, const rad_emitter_choice *choice,
                             rad_vec3 direction, const rad_element_hit *hit) {
    int32_t k = hit_emitter(r, hit);
    if (k < 0) return 0;
    return rad_emitter_choice_pdf(choice, (size_t)k, direction, hit->t);
}

/* Radiance reflected at x (normal n, reflectance rho) of the light straight from the emitters,
 * by `from->light_samples` stratified emitter samples, each weighted against the gather rays
 * that could have found the same point. Sample i is point first + i of the pixel's `total` points
 * in `dimension`. The shadow rays of one point go to Embree 16 at a time (they share the origin
 * and head for the same lamp: a coherent packet). */
static void direct_light(const rad_renderer *r, rad_sample *sample, const rad_gather_origin *from,
                         uint32_t total, uint32_t first, uint32_t dimension, rad_vec3 x,
                         const float rho[3], double out[3]) {
    out[0] = out[1] = out[2] = 0;
    int count = from->light_samples;
    if (!from->choice) return; /* no emitter samples */
    rad_vec3 n = from->normal;
    for (int start = 0; start < count; start += 16) {
        int lanes = count - start < 16 ? count - start : 16;
        rad_emitter_point light[16];
        rad_vec3 position[16];
        double cosine[16];
        int occluded[16], live[16], traced = 0;
        double u_all[16][2];
        rad_sample_2d_run(sample, total, first + (uint32_t)start, lanes, dimension, u_all);
        for (int i = 0; i < lanes; ++i) {
            const double *u = u_all[i];
            live[i] = rad_emitter_choice_sample(from->choice, u[0], u[1], &light[i]) &&
                      (cosine[i] = v3_dot(n, light[i].direction)) > 0;
            if (live[i]) position[traced++] = light[i].position;
        }
        sample->counts->shadow += (uint64_t)traced;
        if (traced == 1) occluded[0] = rad_element_rays_occluded(r->inner_rays, x, position[0]);
        else if (traced > 1) rad_element_rays_occluded16(r->inner_rays, x, position, traced, occluded);
        for (int i = 0, k = 0; i < lanes; ++i) {
            if (!live[i] || occluded[k++]) continue;
            /* Densities over solid angle at x. */
            double cos_x = cosine[i];
            double pdf_gather = cos_x / RAD_PI;
            double weight = rad_power_heuristic(count * light[i].pdf, from->gather_rays * pdf_gather);
            double g = cos_x / light[i].pdf * weight;
            for (int c = 0; c < 3; ++c) out[c] += rho[c] / RAD_PI * light[i].radiance[c] * g;
        }
    }
    for (int c = 0; c < 3; ++c) out[c] /= count;
}

/* Radiance reflected at x (normal n, reflectance rho) of the point, spot and directional
 * lights: each is one point or direction, so it is sampled exactly, with one shadow ray and no
 * weight (no gather ray can find it). */
static void lights_direct(const rad_renderer *r, rad_sample *sample, rad_vec3 x, rad_vec3 n,
                          const float rho[3], double out[3]) {
    for (size_t i = 0; i < r->light_count; ++i) {
        rad_light_arrival arrival;
        if (!rad_light_arrive(&r->lights[i], x, &arrival)) continue;
        double cos_x = v3_dot(n, arrival.direction);
        if (cos_x <= 0) continue;
        if (!rad_light_unblocked(r, i, x, &arrival, sample->counts)) continue;
        for (int c = 0; c < 3; ++c) out[c] += rho[c] / RAD_PI * arrival.irradiance[c] * cos_x;
    }
}

int rad_light_unblocked(const rad_renderer *r, size_t i, rad_vec3 x,
                        const rad_light_arrival *arrival, rad_ray_counts *counts) {
    counts->shadow++;
    if (isinf(arrival->distance)) {
        rad_element_hit blocker;
        return !rad_element_rays_intersect(r->rays, x, arrival->direction, r->rays->epsilon,
                                           INFINITY, &blocker);
    }
    return !rad_element_rays_occluded(r->rays, x, r->lights[i].position);
}

/* cos and sin of 2 pi turn, turn in [0, 1): polynomials on the quarter turn nearest the angle,
 * the quarter chosen by selection rather than a branch, so that a loop of them runs in vector
 * registers (cosine_directions). Error under 2e-9. glibc's sincosf, one call a gather ray, was
 * 5 % of the default render (its double sincos 5 % before that). */
static inline void unit_circle(double turn, double *cos_out, double *sin_out) {
    /* turn = quarter / 4 + r, |r| <= 1/8: the angle 2 pi r lies within pi / 4 of the quarter. */
    int q = (int)(4 * turn + 0.5); /* rounded: turn >= 0 (no floor call) */
    double angle = (2 * RAD_PI) * (turn - 0.25 * q), a2 = angle * angle;
    double sine = angle * (1 + a2 * (-1.0 / 6 + a2 * (1.0 / 120 + a2 * (-1.0 / 5040 +
                                                        a2 * (1.0 / 362880)))));
    double cosine = 1 + a2 * (-0.5 + a2 * (1.0 / 24 + a2 * (-1.0 / 720 + a2 * (1.0 / 40320 +
                                                           a2 * (-1.0 / 3628800)))));
    /* Quarter q turns (cos, sin) by q right angles: (c, s), (-s, c), (-c, -s), (s, -c). */
    int odd = q & 1, half = (q >> 1) & 1;
    double c = odd ? sine : cosine, s = odd ? cosine : sine;
    *cos_out = (odd ^ half) ? -c : c;
    *sin_out = half ? -s : s;
}

/* A cosine-weighted direction about n (basis t, b, n) from the point u of the unit square
 * (Malley's method: the disc's point at radius sqrt(u0) and angle 2 pi u1, lifted to the
 * hemisphere); unit length up to rounding (the ray's frame normalises it). */
static rad_vec3 cosine_direction(rad_vec3 t, rad_vec3 b, rad_vec3 n, const double u[2]) {
    double radius = sqrt(u[0]), z = sqrt(fmax(0.0, 1 - u[0])), c, s;
    unit_circle(u[1], &c, &s);
    double a = radius * c, e = radius * s;
    return v3(a * t.x + e * b.x + z * n.x, a * t.y + e * b.y + z * n.y, a * t.z + e * b.z + z * n.z);
}

/* The same for count <= 16 points at once, the angles in vector registers (the square roots
 * apart: with errno they are calls, which keep a loop scalar). */
static void cosine_directions(rad_vec3 t, rad_vec3 b, rad_vec3 n, const double (*u)[2], int count,
                              rad_vec3 *out) {
    double radius[16], z[16], turn[16], dx[16], dy[16], dz[16];
    for (int i = 0; i < 16; ++i) {
        double u0 = i < count ? u[i][0] : 0;
        radius[i] = sqrt(u0);
        z[i] = sqrt(fmax(0.0, 1 - u0));
        turn[i] = i < count ? u[i][1] : 0;
    }
    for (int i = 0; i < 16; ++i) {
        double c, s;
        unit_circle(turn[i], &c, &s);
        double a = radius[i] * c, e = radius[i] * s;
        dx[i] = a * t.x + e * b.x + z[i] * n.x;
        dy[i] = a * t.y + e * b.y + z[i] * n.y;
        dz[i] = a * t.z + e * b.z + z[i] * n.z;
    }
    for (int i = 0; i < count; ++i) out[i] = v3(dx[i], dy[i], dz[i]);
}

#define PACKET 16 /* gather rays traced together (rad_element_rays_intersect16) */

double rad_gather_emission_weight(const rad_renderer *r, const rad_gather_origin *from,
                                  rad_vec3 direction, const rad_element_hit *hit) {
    if (!from || !from->choice) return 1;
    double pdf_light = choice_hit_pdf(r, from->choice, direction, hit);
    double cos_x = v3_dot(from->normal, direction);
    if (!(pdf_light > 0) || cos_x <= 0) return 1;
    return rad_power_heuristic(from->gather_rays * cos_x / RAD_PI, from->light_samples * pdf_light);
}

/* ------------------------------------------------------------------------------------------- */

void rad_final_gather(const rad_renderer *r, rad_sample *sample, const rad_element_hit *hit,
                      rad_vec3 x, rad_vec3 n, int first_hit, double out[3]) {
    uint32_t element = hit->element;
    float rho[3]; /* the texture's at x on textured surfaces (texture_shading.c) */
    int textured = rad_renderer_albedo(r, element, x, rho);
    rad_visible_emission(r, hit, x, n, rho, out); /* caustics from the map (caustics.c) */
    if (!(rho[0] > 0 || rho[1] > 0 || rho[2] > 0)) return;

    /* The irradiance filter (gather_filter.c) takes untextured first hits only: there rho is
     * one value over the polygon and the filtered radiance can be multiplied back by it. */
    rad_gather_tally *tally = first_hit && !textured ? sample->tally : NULL;
    int rays = sample->gather_rays ? sample->gather_rays : r->settings.final_gather;
    /* This sample's gather points: a run of the pixel's sequence (render.c sets it). */
    uint32_t total = sample->gather_total ? sample->gather_total : sample->count * (uint32_t)rays;
    uint32_t first = sample->gather_total ? sample->gather_first : sample->index * (uint32_t)rays;
    int light_samples = sample->light_samples ? sample->light_samples : r->settings.light_samples;
    /* Dark receivers (the short block's front face, lit by the floor in the block's shadow)
     * gather again over twice the range: the solution read 4 to 8 element sizes away there
     * (the floor's elements across the penumbra) made the face 1.5 % dark (docs/rendering.md,
     * "Dark pixels"). Dark: the element's radiance under render.c's threshold. */
    const float *own = r->element_radiance[element];
    double range = (own[0] + own[1] + own[2]) / 3 < r->dark_radiance ? DARK_SHORT_RANGE : SHORT_RANGE;
    if (r->regather.leaves == RAD_LEAVES_COARSE) range = INFINITY;
    rad_gather_origin from = {n, light_samples, rays, 0, 0, total, tally, range, NULL};
    rad_emitter_choice choice;
    if (r->emitters.count && light_samples > 0) {
        rad_emitter_choice_init(&choice, &r->emitters, x, n);
        from.choice = &choice;
    }

    /* Direct light. */
    double direct[3];
    uint32_t lights = (uint32_t)from.light_samples;
    direct_light(r, sample, &from, sample->count * lights, sample->index * lights, RAD_RENDER_DIM_LIGHT,
                 x, rho, direct);
    lights_direct(r, sample, x, n, rho, direct);
    for (int c = 0; c < 3; ++c) out[c] += direct[c];

    /* Indirect light (and the emitted light they meet, weighted): cosine-weighted rays into the
     * solution. With density cos / pi the estimate of (rho / pi) * integral L cos dw is
     * rho * mean L. */
    double sum[3] = {0, 0, 0}, reflected[3] = {0, 0, 0};
    rad_vec3 t, b;
    v3_basis(n, &t, &b);
    for (int start = 0; start < rays; start += PACKET) {
        int lanes = rays - start < PACKET ? rays - start : PACKET;
        rad_vec3 direction[PACKET];
        rad_element_hit hits[PACKET];
        double u[PACKET][2];
        rad_sample_2d_run(sample, total, first + (uint32_t)start, lanes, RAD_RENDER_DIM_GATHER, u);
        cosine_directions(t, b, n, (const double (*)[2])u, lanes, direction);
        rad_element_rays_intersect16(r->inner_rays, x, direction, lanes, r->rays->epsilon, hits);
        for (int i = 0; i < lanes; ++i) {
            from.ray = first + (uint32_t)(start + i);
            double radiance[3];
            if (tally) tally->ray_emitted[0] = tally->ray_emitted[1] = tally->ray_emitted[2] = 0;
            rad_trace_radiance_hit(r, sample, x, direction[i], &from, &hits[i], radiance);
            for (int c = 0; c < 3; ++c) sum[c] += radiance[c];
            if (tally)
                for (int c = 0; c < 3; ++c) reflected[c] += radiance[c] - tally->ray_emitted[c];
        }
    }
    for (int c = 0; c < 3; ++c) out[c] += rho[c] * sum[c] / rays;
    if (!tally) return;
    tally->gathers++;
    for (int c = 0; c < 3; ++c) {
        tally->reflected[c] += reflected[c] / rays;
        tally->rho[c] = rho[c];
    }
    tally->position[0] += x.x;
    tally->position[1] += x.y;
    tally->position[2] += x.z;
}

/* ------------------------------------------------------------------------------------------- */
/* Short gather rays                                                                            */

/* A gather ray shorter than SHORT_RANGE element sizes (DARK_SHORT_RANGE from dark receivers;
 * the size is the square root of the hit element's area) looks at the solution from closer than its elements resolve: beside a block's base the
 * floor element it meets holds the mean over its area, brighter than the dark corner the ray
 * sees, and the bias does not shrink with more rays. There the radiance is gathered once more
 * (one emitter sample and SHORT_RAYS gather rays from the hit), as the final gathers of photon maps do
 * for nearby hits (Jensen 1996; Christensen 1999), at most SHORT_LEVELS times along a path.
 * 4 sizes rather than 2: the short block's front face, lit only by the floor in its own shadow,
 * was 2-3% too bright at 2 (the shadow's edge inside floor elements), 1.5% at 4, for 12% more
 * rays (docs/rendering.md, "Choosing the defaults"). */

void rad_regather_choose(rad_renderer *r, int leaves) {
    /* A coarse hierarchy's re-gathers keep one ray past the first level: two would multiply at
     * each of its levels. */
    r->regather = leaves == RAD_LEAVES_COARSE
                      ? (struct rad_regather){leaves, COARSE_SHORT_LEVELS, 1, COARSE_FIRST_RAYS, 0}
                  : leaves == RAD_LEAVES_FINE
                      ? (struct rad_regather){leaves, FINE_SHORT_LEVELS, FINE_DEEP_RAYS, SHORT_RAYS, 0}
                      : (struct rad_regather){RAD_LEAVES_UNIFORM, SHORT_LEVELS, SHORT_RAYS, SHORT_RAYS, 0};
    /* The penumbra test sees the emitter table's lamps only: other lights' shadows could cross
     * an element it calls even. */
    r->regather.by_light = r->regather.leaves == RAD_LEAVES_UNIFORM && r->light_count == 0 &&
                           r->sky.kind == RAD_SKY_OFF;
}

rad_status rad_regather_prepare(rad_renderer *r) {
    r->element_near = rad_alloc_zero(r->ctx, r->mesh->element_count + 1, sizeof *r->element_near);
    return r->element_near ? RAD_OK : RAD_ERROR_NO_MEMORY;
}

/* Whether another surface lies within NEAR_SURFACE sizes of element e's centroid, seen along
 * the probes (0 not tested yet, 1 no, 2 yes; threads that ask at once store the same answer). */
static int element_near(const rad_renderer *r, uint32_t e, double size) {
    uint8_t known = atomic_load_explicit(&r->element_near[e], memory_order_relaxed);
    if (known) return known == 2;
    rad_vec3 n = r->mesh->element_normal[e], c = r->mesh->element_centroid[e], t, b;
    v3_basis(n, &t, &b);
    const double along = cos(NEAR_ELEVATION), up = sin(NEAR_ELEVATION);
    int near = 0;
    for (int k = 0; k < NEAR_PROBES && !near; ++k) {
        double turn = (double)k / NEAR_PROBES, cosine, sine;
        unit_circle(turn, &cosine, &sine);
        rad_vec3 d = v3_add(v3_add(v3_scale(t, along * cosine), v3_scale(b, along * sine)),
                            v3_scale(n, up));
        rad_element_hit probe;
        near = rad_element_rays_intersect(r->inner_rays, c, d, r->inner_rays->epsilon,
                                          NEAR_SURFACE * size, &probe);
    }
    atomic_store_explicit(&r->element_near[e], (uint8_t)(1 + near), memory_order_relaxed);
    return near;
}

int rad_gather_is_short(const rad_renderer *r, const rad_gather_origin *from, const rad_element_hit *hit) {
    if (!from || from->level >= r->regather.levels) return 0;
    double size = sqrt(r->mesh->element_area[hit->element]);
    if (!(hit->t < from->short_range * size)) return 0;
    if (!r->regather.by_light || hit->t < EVEN_RANGE * size) return 1;
    return element_near(r, hit->element, size) || rad_penumbra_element_uneven(r, hit->element);
}

void rad_gather_short(const rad_renderer *r, rad_sample *sample, const rad_gather_origin *from,
                      const rad_element_hit *hit, rad_vec3 y, rad_vec3 n, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    const float *rho = r->element_reflectance[hit->element];
    if (!(rho[0] > 0 || rho[1] > 0 || rho[2] > 0)) return;
    /* The parent's place in the sampler: the pixel's gather points and its point among them. */
    uint32_t run = from->run, point = from->ray;
    uint32_t dimension = RAD_RENDER_DIM_SHORT + 2 * (uint32_t)from->level;
    /* The re-gather's own rays are short within NEAR_RANGE on a uniform mesh; on a hierarchy's
     * leaves by the range its parent's were, SHORT_RANGE after an infinite one (every first
     * gather ray re-gathered). */
    const int rays = from->level == 0 ? r->regather.first_rays : r->regather.rays;
    double range = isinf(from->short_range) ? SHORT_RANGE
                   : r->regather.leaves == RAD_LEAVES_UNIFORM ? NEAR_RANGE
                                                                     : from->short_range;
    rad_gather_origin next = {n, r->emitters.count ? 1 : 0, rays, point, from->level + 1, run, NULL,
                              range, NULL};
    rad_emitter_choice choice;
    if (r->emitters.count) {
        rad_emitter_choice_init(&choice, &r->emitters, y, n);
        next.choice = &choice;
    }
    double direct[3], gathered[3] = {0, 0, 0};
    direct_light(r, sample, &next, run, point, dimension, y, rho, direct);
    lights_direct(r, sample, y, n, rho, direct); /* point, spot, directional: exact at y */
    rad_vec3 t, b;
    v3_basis(n, &t, &b);
    /* Its rays: an aligned run of `rays` points of the pixel's run * rays, stratified together. */
    for (int k = 0; k < rays; ++k) {
        double u[2], radiance[3];
        rad_sample_2d_at(sample, run * (uint32_t)rays, point * (uint32_t)rays + (uint32_t)k,
                         dimension + 1, u);
        rad_trace_radiance(r, sample, y, cosine_direction(t, b, n, u), &next, radiance);
        for (int c = 0; c < 3; ++c) gathered[c] += radiance[c];
    }
    for (int c = 0; c < 3; ++c) out[c] = direct[c] + rho[c] * gathered[c] / rays;
}
