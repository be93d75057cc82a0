/* vec3.h - small 3-vector math, header only. Doubles: geometry and form factors need them. */
#ifndef RAD_CORE_VEC3_H
#define RAD_CORE_VEC3_H

#include <math.h>
#include <stddef.h>

typedef struct rad_vec3 {
    double x, y, z;
} rad_vec3;

#define RAD_PI 3.14159265358979323846

static inline rad_vec3 v3(double x, double y, double z) { return (rad_vec3){x, y, z}; }
static inline rad_vec3 v3_add(rad_vec3 a, rad_vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline rad_vec3 v3_sub(rad_vec3 a, rad_vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline rad_vec3 v3_scale(rad_vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline rad_vec3 v3_mul(rad_vec3 a, rad_vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline double v3_dot(rad_vec3 a, rad_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline rad_vec3 v3_cross(rad_vec3 a, rad_vec3 b) {
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3_length(rad_vec3 a) { return sqrt(v3_dot(a, a)); }
static inline rad_vec3 v3_normalize(rad_vec3 a) {
    double length = v3_length(a);
    return length > 0 ? v3_scale(a, 1.0 / length) : a;
}
static inline rad_vec3 v3_lerp(rad_vec3 a, rad_vec3 b, double t) {
    return v3(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t);
}
static inline double v3_max_component(rad_vec3 a) {
    double m = a.x > a.y ? a.x : a.y;
    return m > a.z ? m : a.z;
}
/* Componentwise smaller and larger, as fmin and fmax (a NaN in b gives a's) but inlined. */
static inline rad_vec3 v3_min(rad_vec3 a, rad_vec3 b) {
    return v3(a.x < b.x || b.x != b.x ? a.x : b.x, a.y < b.y || b.y != b.y ? a.y : b.y,
              a.z < b.z || b.z != b.z ? a.z : b.z);
}
static inline rad_vec3 v3_max(rad_vec3 a, rad_vec3 b) {
    return v3(a.x > b.x || b.x != b.x ? a.x : b.x, a.y > b.y || b.y != b.y ? a.y : b.y,
              a.z > b.z || b.z != b.z ? a.z : b.z);
}
static inline double v3_get(rad_vec3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }

/* Newell's normal of a polygon p[0..n-1]: perpendicular to it, by the right-hand rule of its
 * winding, and twice its area long (any planar polygon, convex or not). */
static inline rad_vec3 v3_newell_normal(const rad_vec3 *p, size_t n) {
    rad_vec3 normal = v3(0, 0, 0);
    for (size_t k = 0; k < n; ++k) {
        rad_vec3 a = p[k], b = p[(k + 1) % n];
        normal.x += (a.y - b.y) * (a.z + b.z);
        normal.y += (a.z - b.z) * (a.x + b.x);
        normal.z += (a.x - b.x) * (a.y + b.y);
    }
    return normal;
}

/* An orthonormal basis (t, b) around a unit normal n (Duff et al. 2017). */
static inline void v3_basis(rad_vec3 n, rad_vec3 *t, rad_vec3 *b) {
    double sign = copysign(1.0, n.z);
    double a = -1.0 / (sign + n.z);
    double c = n.x * n.y * a;
    *t = v3(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
    *b = v3(c, sign + n.y * n.y * a, -n.y);
}

#endif
