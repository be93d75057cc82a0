/* bsdf.c - Lambert, perfect and GGX mirrors, smooth glass (see bsdf.h).
 *
 * References: Walter, Marschner, Li & Torrance 2007, "Microfacet models for refraction through
 * rough surfaces" (GGX distribution, height-correlated Smith masking); Heitz 2018, "Sampling the
 * GGX distribution of visible normals"; Veach 1997, ch. 5 (non-symmetric scattering at
 * refraction); Born & Wolf (Fresnel equations). */
#include "scene/bsdf.h"

/* Index of refraction used when a material leaves it zero (zeroed structs are valid). */
#define DEFAULT_IOR 1.5

static double largest(const double c[3]) { return fmax(c[0], fmax(c[1], c[2])); }

static double positive(double x) { return x > 0 ? x : 0; }

double rad_fresnel_dielectric(double cos_incident, double eta_incident, double eta_transmitted) {
    double cos_i = fmin(fabs(cos_incident), 1.0);
    double eta = eta_incident / eta_transmitted;
    double sin2_t = eta * eta * (1 - cos_i * cos_i);
    if (sin2_t >= 1) return 1; /* total internal reflection */
    double cos_t = sqrt(1 - sin2_t);
    double rs = (eta_incident * cos_i - eta_transmitted * cos_t) /
                (eta_incident * cos_i + eta_transmitted * cos_t);
    double rp = (eta_transmitted * cos_i - eta_incident * cos_t) /
                (eta_transmitted * cos_i + eta_incident * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

static double ior_of(const rad_material *m) {
    return m->ior > 1e-3 && isfinite(m->ior) ? m->ior : DEFAULT_IOR;
}

/* ---- GGX, in a local frame where the normal is +z ------------------------------------------ */

static double ggx_alpha(const rad_material *m) {
    double r = fmin(fmax(m->roughness, 0.0), 1.0);
    return fmax(r * r, 1e-4); /* keep the lobe finite */
}

static double ggx_d(double cos_h, double alpha) {
    double a2 = alpha * alpha;
    double t = cos_h * cos_h * (a2 - 1) + 1;
    return a2 / (RAD_PI * t * t);
}

/* Smith's Lambda for GGX. */
static double ggx_lambda(double cos_theta, double alpha) {
    double c2 = cos_theta * cos_theta;
    if (c2 >= 1) return 0;
    double tan2 = (1 - c2) / c2;
    return 0.5 * (-1 + sqrt(1 + alpha * alpha * tan2));
}

/* A visible normal for the view v (local, v.z > 0), Heitz 2018. */
static rad_vec3 ggx_sample_visible_normal(rad_vec3 v, double alpha, double u1, double u2) {
    rad_vec3 vh = v3_normalize(v3(alpha * v.x, alpha * v.y, v.z));
    double length2 = vh.x * vh.x + vh.y * vh.y;
    rad_vec3 t1 = length2 > 0 ? v3_scale(v3(-vh.y, vh.x, 0), 1 / sqrt(length2)) : v3(1, 0, 0);
    rad_vec3 t2 = v3_cross(vh, t1);
    double r = sqrt(u1), phi = 2 * RAD_PI * u2;
    double p1 = r * cos(phi), p2 = r * sin(phi);
    double s = 0.5 * (1 + vh.z);
    p2 = (1 - s) * sqrt(positive(1 - p1 * p1)) + s * p2;
    rad_vec3 nh = v3_add(v3_add(v3_scale(t1, p1), v3_scale(t2, p2)),
                         v3_scale(vh, sqrt(positive(1 - p1 * p1 - p2 * p2))));
    return v3_normalize(v3(alpha * nh.x, alpha * nh.y, fmax(nh.z, 1e-9)));
}

/* The GGX lobe for local wo, wi (both above): f (scalar, before the tint) and the pdf of
 * visible-normal sampling. */
static double ggx_eval(rad_vec3 wo, rad_vec3 wi, double alpha, double *pdf) {
    *pdf = 0;
    if (wo.z <= 0 || wi.z <= 0) return 0;
    rad_vec3 h = v3_normalize(v3_add(wo, wi));
    double d = ggx_d(h.z, alpha);
    double lambda_o = ggx_lambda(wo.z, alpha), lambda_i = ggx_lambda(wi.z, alpha);
    double g1 = 1 / (1 + lambda_o);
    double g2 = 1 / (1 + lambda_o + lambda_i);
    *pdf = g1 * d / (4 * wo.z);
    return d * g2 / (4 * wo.z * wi.z);
}

typedef struct frame {
    rad_vec3 t, b, n;
} frame;

static frame frame_of(rad_vec3 n) {
    frame f;
    f.n = n;
    v3_basis(n, &f.t, &f.b);
    return f;
}
static rad_vec3 to_local(const frame *f, rad_vec3 w) {
    return v3(v3_dot(w, f->t), v3_dot(w, f->b), v3_dot(w, f->n));
}
static rad_vec3 to_world(const frame *f, rad_vec3 w) {
    return v3_add(v3_add(v3_scale(f->t, w.x), v3_scale(f->b, w.y)), v3_scale(f->n, w.z));
}

/* ---- lobe selection ------------------------------------------------------------------------ */

/* Probability of picking the diffuse lobe of a mirror material (by the largest channel). */
static double diffuse_probability(const rad_material *m) {
    double d = largest(m->reflectance), s = largest(m->specular);
    d = positive(d);
    s = positive(s);
    if (d + s <= 0) return 0;
    return d / (d + s);
}

int rad_bsdf_is_delta(const rad_material *m) {
    if (m->kind == RAD_MATERIAL_GLASS) return 1;
    if (m->kind == RAD_MATERIAL_MIRROR) return m->roughness <= 0 && largest(m->reflectance) <= 0;
    return 0;
}

int rad_bsdf_has_smooth_lobe(const rad_material *m) {
    if (m->kind == RAD_MATERIAL_GLASS) return 0;
    if (m->kind == RAD_MATERIAL_MIRROR)
        return largest(m->reflectance) > 0 || (m->roughness > 0 && largest(m->specular) > 0);
    return largest(m->reflectance) > 0;
}

/* ---- evaluation ------------------------------------------------------------------------------ */

int rad_bsdf_eval(const rad_material *m, rad_vec3 normal, rad_vec3 wo, rad_vec3 wi, double f[3],
                  double *pdf) {
    f[0] = f[1] = f[2] = 0;
    *pdf = 0;
    double cos_o = v3_dot(wo, normal), cos_i = v3_dot(wi, normal);
    if (m->kind == RAD_MATERIAL_GLASS || cos_o <= 0 || cos_i <= 0) return 0;
    if (m->kind == RAD_MATERIAL_DIFFUSE) {
        for (int c = 0; c < 3; ++c) f[c] = m->reflectance[c] / RAD_PI;
        *pdf = cos_i / RAD_PI;
        return largest(m->reflectance) > 0;
    }
    /* Mirror: diffuse part plus, when rough, the GGX part. */
    double p_diffuse = diffuse_probability(m);
    for (int c = 0; c < 3; ++c) f[c] = positive(m->reflectance[c]) / RAD_PI;
    *pdf = p_diffuse * cos_i / RAD_PI;
    if (m->roughness > 0) {
        frame fr = frame_of(normal);
        double ggx_pdf;
        double ggx = ggx_eval(to_local(&fr, wo), to_local(&fr, wi), ggx_alpha(m), &ggx_pdf);
        for (int c = 0; c < 3; ++c) f[c] += positive(m->specular[c]) * ggx;
        *pdf += (1 - p_diffuse) * ggx_pdf;
    }
    return largest(f) > 0;
}

/* ---- sampling ------------------------------------------------------------------------------ */

static rad_lobe absorbed(rad_bsdf_sample *out) {
    out->weight[0] = out->weight[1] = out->weight[2] = 0;
    out->pdf = 0;
    out->delta = 0;
    out->lobe = RAD_LOBE_NONE;
    return RAD_LOBE_NONE;
}

/* Cosine-weighted direction around n (Malley's method). */
static rad_vec3 sample_cosine(rad_vec3 n, double u1, double u2) {
    double r = sqrt(u1), phi = 2 * RAD_PI * u2;
    double x = r * cos(phi), y = r * sin(phi), z = sqrt(positive(1 - u1));
    frame fr = frame_of(n);
    return v3_normalize(to_world(&fr, v3(x, y, z)));
}

double rad_bsdf_glass_reflectance(const rad_material *m, rad_vec3 normal, rad_vec3 wo) {
    double cos_o = v3_dot(wo, normal);
    double ior = ior_of(m);
    return cos_o > 0 ? rad_fresnel_dielectric(cos_o, 1, ior) : rad_fresnel_dielectric(-cos_o, ior, 1);
}

static rad_lobe sample_glass(const rad_material *m, rad_vec3 normal, rad_vec3 wo,
                             const double u[3], rad_bsdf_sample *out) {
    double cos_o = v3_dot(wo, normal);
    if (cos_o == 0) return absorbed(out);
    int entering = cos_o > 0;
    rad_vec3 n = entering ? normal : v3_scale(normal, -1);
    double cos_i = fabs(cos_o);
    double ior = ior_of(m);
    double eta_o = entering ? 1 : ior, eta_t = entering ? ior : 1;
    double fresnel = rad_fresnel_dielectric(cos_i, eta_o, eta_t);
    out->pdf = 0;
    out->delta = 1;
    if (u[0] < fresnel) {
        /* Reflection, chosen with probability F: the weight F / F is the tint. */
        out->direction = rad_reflect(wo, n);
        for (int c = 0; c < 3; ++c) out->weight[c] = positive(m->specular[c]);
        out->lobe = RAD_LOBE_SPECULAR;
        return out->lobe;
    }
    /* Refraction (Snell), chosen with probability 1 - F; radiance scales by (eta_o/eta_t)^2. */
    double eta = eta_o / eta_t;
    double sin2_t = eta * eta * (1 - cos_i * cos_i);
    double cos_t = sqrt(positive(1 - sin2_t));
    out->direction = v3_normalize(v3_add(v3_scale(wo, -eta), v3_scale(n, eta * cos_i - cos_t)));
    double scale = eta * eta;
    for (int c = 0; c < 3; ++c) out->weight[c] = positive(m->specular[c]) * scale;
    out->lobe = RAD_LOBE_TRANSMISSION;
    return out->lobe;
}

rad_lobe rad_bsdf_sample_direction(const rad_material *m, rad_vec3 normal, rad_vec3 wo,
                                   const double u[3], rad_bsdf_sample *out) {
    if (m->kind == RAD_MATERIAL_GLASS) return sample_glass(m, normal, wo, u, out);
    double cos_o = v3_dot(wo, normal);
    if (cos_o <= 0) return absorbed(out); /* the back of a one-sided surface */

    if (m->kind == RAD_MATERIAL_DIFFUSE) {
        if (largest(m->reflectance) <= 0) return absorbed(out);
        out->direction = sample_cosine(normal, u[1], u[2]);
        double cos_i = v3_dot(out->direction, normal);
        if (cos_i <= 0) return absorbed(out);
        for (int c = 0; c < 3; ++c) out->weight[c] = positive(m->reflectance[c]);
        out->pdf = cos_i / RAD_PI;
        out->delta = 0;
        out->lobe = RAD_LOBE_DIFFUSE;
        return out->lobe;
    }

    /* Mirror: pick the diffuse or the specular lobe. */
    double p_diffuse = diffuse_probability(m);
    if (p_diffuse <= 0 && largest(m->specular) <= 0) return absorbed(out);
    int diffuse = u[0] < p_diffuse;
    if (!diffuse && m->roughness <= 0) {
        /* Perfect mirror: a delta lobe chosen with probability 1 - p_diffuse. */
        out->direction = rad_reflect(wo, normal);
        for (int c = 0; c < 3; ++c) out->weight[c] = positive(m->specular[c]) / (1 - p_diffuse);
        out->pdf = 0;
        out->delta = 1;
        out->lobe = RAD_LOBE_SPECULAR;
        return out->lobe;
    }
    if (diffuse) {
        out->direction = sample_cosine(normal, u[1], u[2]);
    } else {
        frame fr = frame_of(normal);
        rad_vec3 h = ggx_sample_visible_normal(to_local(&fr, wo), ggx_alpha(m), u[1], u[2]);
        out->direction = v3_normalize(rad_reflect(wo, to_world(&fr, h)));
    }
    double cos_i = v3_dot(out->direction, normal);
    if (cos_i <= 0) return absorbed(out);
    /* The weight of the whole non-delta mixture (one-sample MIS between the lobes). */
    double f[3], pdf;
    rad_bsdf_eval(m, normal, wo, out->direction, f, &pdf);
    if (!(pdf > 0)) return absorbed(out);
    for (int c = 0; c < 3; ++c) out->weight[c] = f[c] * cos_i / pdf;
    out->pdf = pdf;
    out->delta = 0;
    out->lobe = diffuse ? RAD_LOBE_DIFFUSE : RAD_LOBE_GLOSSY;
    return out->lobe;
}

rad_vec3 rad_cosine_direction(rad_vec3 n, double u1, double u2) {
    rad_vec3 t, b;
    v3_basis(n, &t, &b);
    double r = sqrt(u1), phi = 2 * RAD_PI * u2;
    double z = sqrt(fmax(0, 1 - u1));
    return v3_normalize(v3_add(v3_scale(n, z), v3_add(v3_scale(t, r * cos(phi)),
                                                       v3_scale(b, r * sin(phi)))));
}
