/* test_bsdf.c - materials: exact Fresnel values, sampling weights against the integral of
 * f * cos computed independently (uniform directions and rad_bsdf_eval), pdfs that integrate to
 * what sampling lands on, mirror and glass geometry, one-sided surfaces. */
#include "core/rng.h"
#include "scene/bsdf.h"
#include "test.h"

static rad_material material(rad_material_kind kind, double rho, double spec, double roughness) {
    rad_material m = {0};
    m.kind = kind;
    for (int c = 0; c < 3; ++c) {
        m.reflectance[c] = rho;
        m.specular[c] = spec;
    }
    m.roughness = roughness;
    m.ior = 1.5;
    return m;
}

static rad_vec3 direction_at(double cos_theta, double phi) {
    double s = sqrt(1 - cos_theta * cos_theta);
    return v3(s * cos(phi), s * sin(phi), cos_theta);
}

static void test_fresnel(void) {
    /* Normal incidence: ((n - 1) / (n + 1))^2. */
    CHECK_NEAR(rad_fresnel_dielectric(1, 1, 1.5), 0.04, 1e-12);
    CHECK_NEAR(rad_fresnel_dielectric(1, 1.5, 1), 0.04, 1e-12);
    /* Grazing: total reflection. */
    CHECK_NEAR(rad_fresnel_dielectric(1e-9, 1, 1.5), 1, 1e-6);
    /* Beyond the critical angle asin(1/1.5) inside glass: total internal reflection. */
    double critical = asin(1 / 1.5);
    CHECK(rad_fresnel_dielectric(cos(critical + 0.01), 1.5, 1) == 1);
    CHECK(rad_fresnel_dielectric(cos(critical - 0.01), 1.5, 1) < 1);
    /* Brewster's angle atan(n): the p polarisation vanishes, F = rs^2 / 2. */
    double brewster = atan(1.5);
    double ci = cos(brewster), ct = cos(asin(sin(brewster) / 1.5));
    double rs = (ci - 1.5 * ct) / (ci + 1.5 * ct);
    CHECK_NEAR(rad_fresnel_dielectric(ci, 1, 1.5), 0.5 * rs * rs, 1e-12);
    /* Reciprocity: the same boundary crossed either way reflects the same fraction. */
    double cos_inside = cos(asin(sin(0.7) / 1.5));
    CHECK_NEAR(rad_fresnel_dielectric(cos(0.7), 1, 1.5), rad_fresnel_dielectric(cos_inside, 1.5, 1),
               1e-12);
}

/* E[weight] by BSDF sampling vs. the integral of f * cos over the sphere by uniform directions,
 * and the pdf's integral vs. the fraction of samples that are not absorbed. */
static void check_estimators(const rad_material *m, rad_vec3 wo, double tolerance) {
    rad_vec3 n = v3(0, 0, 1);
    rad_rng rng = rad_rng_make(7, 1);
    const int samples = 400000;
    double sampled[3] = {0, 0, 0}, integral[3] = {0, 0, 0}, pdf_integral = 0;
    int kept = 0, bad_pdf = 0;
    for (int i = 0; i < samples; ++i) {
        double u[3] = {rad_rng_uniform(&rng), rad_rng_uniform(&rng), rad_rng_uniform(&rng)};
        rad_bsdf_sample s;
        if (rad_bsdf_sample_direction(m, n, wo, u, &s) != RAD_LOBE_NONE) {
            ++kept;
            for (int c = 0; c < 3; ++c) sampled[c] += s.weight[c];
            double f[3], pdf;
            rad_bsdf_eval(m, n, wo, s.direction, f, &pdf);
            if (!s.delta && fabs(pdf - s.pdf) > 1e-9 * pdf) ++bad_pdf;
        }
        /* Uniform over the upper hemisphere, pdf 1 / (2 pi). */
        rad_vec3 wi = direction_at(rad_rng_uniform(&rng), 2 * RAD_PI * rad_rng_uniform(&rng));
        double f[3], pdf;
        rad_bsdf_eval(m, n, wo, wi, f, &pdf);
        for (int c = 0; c < 3; ++c) integral[c] += f[c] * wi.z * 2 * RAD_PI;
        pdf_integral += pdf * 2 * RAD_PI;
    }
    CHECK(bad_pdf == 0);
    CHECK_NEAR(sampled[0] / samples, integral[0] / samples, tolerance);
    CHECK_NEAR(pdf_integral / samples, (double)kept / samples, tolerance);
}

static void test_lambert(void) {
    rad_material m = material(RAD_MATERIAL_DIFFUSE, 0.6, 0, 0);
    rad_vec3 n = v3(0, 0, 1);
    rad_vec3 wo = direction_at(0.3, 1.0);
    double u[3] = {0.5, 0.25, 0.75};
    rad_bsdf_sample s;
    CHECK(rad_bsdf_sample_direction(&m, n, wo, u, &s) == RAD_LOBE_DIFFUSE);
    CHECK_NEAR(s.weight[0], 0.6, 1e-12); /* f cos / pdf = rho exactly */
    CHECK(s.direction.z > 0 && !s.delta);
    CHECK_NEAR(s.pdf, s.direction.z / RAD_PI, 1e-12);
    double f[3], pdf;
    CHECK(rad_bsdf_eval(&m, n, wo, s.direction, f, &pdf));
    CHECK_NEAR(f[1], 0.6 / RAD_PI, 1e-12);
    /* One-sided: seen from the back, or light from behind, nothing. */
    CHECK(rad_bsdf_sample_direction(&m, n, v3(0, 0, -1), u, &s) == RAD_LOBE_NONE);
    CHECK(s.weight[0] == 0);
    CHECK(!rad_bsdf_eval(&m, n, wo, v3(0, 0.6, -0.8), f, &pdf));
    CHECK(!rad_bsdf_is_delta(&m) && rad_bsdf_has_smooth_lobe(&m));
    check_estimators(&m, wo, 0.01);
}

static void test_mirror(void) {
    rad_material m = material(RAD_MATERIAL_MIRROR, 0, 0.9, 0);
    m.specular[2] = 0.5;
    rad_vec3 n = v3(0, 0, 1);
    rad_vec3 wo = v3_normalize(v3(1, 2, 3));
    double u[3] = {0.3, 0.1, 0.9};
    rad_bsdf_sample s;
    CHECK(rad_bsdf_sample_direction(&m, n, wo, u, &s) == RAD_LOBE_SPECULAR);
    CHECK(s.delta);
    CHECK_NEAR(s.direction.x, -wo.x, 1e-12);
    CHECK_NEAR(s.direction.y, -wo.y, 1e-12);
    CHECK_NEAR(s.direction.z, wo.z, 1e-12);
    CHECK_NEAR(s.weight[0], 0.9, 1e-12);
    CHECK_NEAR(s.weight[2], 0.5, 1e-12);
    CHECK(rad_bsdf_is_delta(&m) && !rad_bsdf_has_smooth_lobe(&m));
    double f[3], pdf;
    CHECK(!rad_bsdf_eval(&m, n, wo, s.direction, f, &pdf));
    /* The back of a mirror is black. */
    CHECK(rad_bsdf_sample_direction(&m, n, v3(0, 0, -1), u, &s) == RAD_LOBE_NONE);

    /* Diffuse + perfect mirror: expected weight rho + spec. */
    rad_material mixed = material(RAD_MATERIAL_MIRROR, 0.3, 0.5, 0);
    rad_rng rng = rad_rng_make(3, 3);
    double sum = 0;
    const int samples = 200000;
    for (int i = 0; i < samples; ++i) {
        double v[3] = {rad_rng_uniform(&rng), rad_rng_uniform(&rng), rad_rng_uniform(&rng)};
        if (rad_bsdf_sample_direction(&mixed, n, wo, v, &s)) sum += s.weight[0];
    }
    CHECK_NEAR(sum / samples, 0.8, 0.01);
    CHECK(!rad_bsdf_is_delta(&mixed) && rad_bsdf_has_smooth_lobe(&mixed));
}

static void test_glossy(void) {
    /* A GGX lobe: sampling and eval agree, and it never creates energy. */
    const double roughness[] = {0.2, 0.5, 0.9};
    for (int r = 0; r < 3; ++r) {
        rad_material m = material(RAD_MATERIAL_MIRROR, 0, 1, roughness[r]);
        for (double c = 0.2; c < 1; c += 0.35) {
            rad_vec3 wo = direction_at(c, 0.4);
            check_estimators(&m, wo, 0.02);
        }
        rad_material mixed = material(RAD_MATERIAL_MIRROR, 0.4, 0.5, roughness[r]);
        check_estimators(&mixed, direction_at(0.7, 2.0), 0.02);
    }
    /* Energy: the albedo of a white GGX lobe is at most 1 and near 1 at low roughness. */
    rad_material m = material(RAD_MATERIAL_MIRROR, 0, 1, 0.1);
    rad_rng rng = rad_rng_make(11, 2);
    double sum = 0;
    const int samples = 100000;
    for (int i = 0; i < samples; ++i) {
        double u[3] = {rad_rng_uniform(&rng), rad_rng_uniform(&rng), rad_rng_uniform(&rng)};
        rad_bsdf_sample s;
        if (rad_bsdf_sample_direction(&m, v3(0, 0, 1), direction_at(0.9, 0), u, &s))
            sum += s.weight[0];
    }
    CHECK(sum / samples <= 1.0 + 1e-9);
    CHECK(sum / samples > 0.97);
}

static void test_glass(void) {
    rad_material m = material(RAD_MATERIAL_GLASS, 0.5, 1, 0);
    rad_vec3 n = v3(0, 0, 1);
    CHECK(rad_bsdf_is_delta(&m) && !rad_bsdf_has_smooth_lobe(&m));
    /* Entering at 45 degrees: Snell's law sin(t) = sin(45) / 1.5, weight 1 / 1.5^2. */
    rad_vec3 wo = v3_normalize(v3(1, 0, 1));
    double u[3] = {0.99, 0.5, 0.5};
    rad_bsdf_sample s;
    CHECK(rad_bsdf_sample_direction(&m, n, wo, u, &s) == RAD_LOBE_TRANSMISSION);
    CHECK(s.delta && s.direction.z < 0);
    CHECK_NEAR(s.direction.x, -sin(RAD_PI / 4) / 1.5, 1e-12);
    CHECK_NEAR(v3_length(s.direction), 1, 1e-12);
    CHECK_NEAR(s.weight[0], 1 / 2.25, 1e-12);
    /* Reflection with probability F. */
    double fresnel = rad_fresnel_dielectric(cos(RAD_PI / 4), 1, 1.5);
    u[0] = 0.5 * fresnel;
    CHECK(rad_bsdf_sample_direction(&m, n, wo, u, &s) == RAD_LOBE_SPECULAR);
    CHECK_NEAR(s.direction.x, -wo.x, 1e-12);
    CHECK_NEAR(s.direction.z, wo.z, 1e-12);
    CHECK_NEAR(s.weight[0], 1, 1e-12);
    /* Leaving the glass: the inverse refraction, weight 1.5^2. */
    rad_vec3 inside = v3(sin(RAD_PI / 4) / 1.5, 0, -sqrt(1 - 0.5 / 2.25));
    u[0] = 0.999;
    CHECK(rad_bsdf_sample_direction(&m, n, inside, u, &s) == RAD_LOBE_TRANSMISSION);
    CHECK_NEAR(s.direction.x, -sin(RAD_PI / 4), 1e-12);
    CHECK(s.direction.z > 0);
    CHECK_NEAR(s.weight[0], 2.25, 1e-12);
    /* Total internal reflection: always reflected, whatever u[0]. */
    rad_vec3 steep = v3_normalize(v3(1, 0, -0.3));
    CHECK(rad_bsdf_sample_direction(&m, n, steep, u, &s) == RAD_LOBE_SPECULAR);
    CHECK(s.direction.z < 0);
    /* The fraction reflected is F. */
    rad_rng rng = rad_rng_make(5, 9);
    int reflected = 0;
    const int samples = 100000;
    for (int i = 0; i < samples; ++i) {
        double v[3] = {rad_rng_uniform(&rng), 0.5, 0.5};
        if (rad_bsdf_sample_direction(&m, n, wo, v, &s) == RAD_LOBE_SPECULAR) ++reflected;
    }
    CHECK_NEAR((double)reflected / samples, fresnel, 0.003);
}

int main(void) {
    test_fresnel();
    test_lambert();
    test_mirror();
    test_glossy();
    test_glass();
    return test_finish();
}
