/* The packet kernel, instantiated once per SIMD width by trace_packet.c.
 * Parameters (macros): KW lanes, K(name) a per-width name, KATTR target attributes,
 * KSQRT(x) a lane-wise square root of a KW-lane vector. */
#define vd K(vd)
#define vi K(vi)
typedef double vd __attribute__((vector_size(KW * sizeof(double))));
typedef long long vi __attribute__((vector_size(KW * sizeof(long long))));

KATTR VINLINE vd K(vsqrt)(vd x)
{
    return (vd)KSQRT(x);
}

KATTR VINLINE vd K(vsel)(vi m, vd a, vd b) /* m ? a : b, lane-wise */
{
    return (vd)(((vi)a & m) | ((vi)b & ~m));
}

KATTR VINLINE vd K(vsplat)(double x)
{
    vd r;
    for (int i = 0; i < KW; i++)
        r[i] = x;
    return r;
}

KATTR VINLINE int K(vany)(vi m)
{
    long long a = 0;
    for (int i = 0; i < KW; i++)
        a |= m[i];
    return a != 0;
}

KATTR VINLINE vd K(vabs)(vd x)
{
    vi sign = (vi)K(vsplat)(-0.0);
    return (vd)((vi)x & ~sign);
}

KATTR VINLINE vd K(vcopysign)(vd mag, vd sgn) /* mag >= 0 */
{
    vi sign = (vi)K(vsplat)(-0.0);
    return (vd)((vi)mag | ((vi)sgn & sign));
}

KATTR VINLINE vi K(visfinite)(vd x)
{
    return K(vabs)(x) <= K(vsplat)(INFINITY);
}

/* The lanes' rays: position, direction, transmittance, and which are still going. */
typedef struct {
    vd ox, oy, oz, dx, dy, dz, eta;
    vi alive;
} K(rays);

/* A surface's hit, lane-wise: distance, point, normal, the index ratio n1 / n2, whether
 * the ray meets the surface and whether within its semi-diameter. */
typedef struct {
    vd t, px, py, pz, nx, ny, nz, e;
    vi hit, inside;
} K(hit);

/* Loads count rays (unused lanes padded with copies of lane 0, so they compute harmless
 * numbers) and their index tables; a ray with a non-finite number is invalid at once. */
KATTR VINLINE void K(load)(const lens_t *lens, const double *const *n, int count,
                           const lens_ray *r, K(rays) *R, const double *nl[KW], int status[KW],
                           int surface[KW])
{
    for (int l = 0; l < KW; l++) {
        int s = l < count ? l : 0;
        R->ox[l] = r[s].o[0], R->oy[l] = r[s].o[1], R->oz[l] = r[s].o[2];
        R->dx[l] = r[s].d[0], R->dy[l] = r[s].d[1], R->dz[l] = r[s].d[2];
        nl[l] = n[s];
    }
    R->eta = K(vsplat)(1.0);
    R->alive = K(visfinite)(R->ox) & K(visfinite)(R->oy) & K(visfinite)(R->oz) &
               K(visfinite)(R->dx) & K(visfinite)(R->dy) & K(visfinite)(R->dz);
    for (int l = 0; l < KW; l++) {
        status[l] = R->alive[l] ? TRACE_PASSED : TRACE_INVALID;
        surface[l] = R->alive[l] ? -1 : (int)lens->nsurf - 1;
    }
}

/* The hit of a sphere or conic (no asphere terms) from n1 (sensor side) into n2:
 * c (x^2 + y^2 + k1 z^2) - 2 z = 0 along the ray (intersect.c, vectorised). */
KATTR VINLINE void K(conic_hit)(const lens_surface *s, double c, double k1, double vz,
                                double sd2, vd n1, vd n2, const K(rays) *R, K(hit) *H)
{
    const vd one = K(vsplat)(1.0), zero = K(vsplat)(0.0);
    vd qz = R->oz - vz;
    vd A = c * (R->dx * R->dx + R->dy * R->dy + k1 * R->dz * R->dz);
    vd B = c * (R->ox * R->dx + R->oy * R->dy + k1 * qz * R->dz) - R->dz;
    vd C = c * (R->ox * R->ox + R->oy * R->oy + k1 * qz * qz) - 2.0 * qz;
    vd disc = B * B - A * C;
    vi dok = disc >= zero;
    vd sq = K(vsqrt)(K(vsel)(dok, disc, zero));
    vd qq = -(B + K(vcopysign)(sq, B));
    /* The near root C / qq and the index ratio n1 / n2 share one division (the divider
     * is the bottleneck); the far root qq / A needs none for a sphere, where
     * A = c |d|^2 = c. qq = 0 only for a ray tangent at its own origin. */
    vi qnz = qq != zero;
    vd qs = K(vsel)(qnz, qq, one);
    vd inv = one / (qs * n2);
    vd r0 = C * n2 * inv, r1 = s->conic == 0 ? qq * s->radius : qq / A;
    H->e = n1 * qs * inv;
    vd z0 = qz + r0 * R->dz, z1 = qz + r1 * R->dz;
    vd lim = K(vsplat)(1.0 + 1e-12), tmin = K(vsplat)(ISECT_T_MIN);
    vi v0 = dok & qnz & K(visfinite)(r0) & (r0 > tmin) & (k1 * c * z0 <= lim);
    vi v1 = dok & K(visfinite)(r1) & (r1 > tmin) & (k1 * c * z1 <= lim);
    H->t = K(vsel)(v0 & v1, K(vsel)(r0 < r1, r0, r1), K(vsel)(v0, r0, r1));
    H->hit = v0 | v1;
    H->px = R->ox + H->t * R->dx, H->py = R->oy + H->t * R->dy;
    vd zr = qz + H->t * R->dz;
    H->pz = zr + vz;
    H->nx = c * H->px, H->ny = c * H->py, H->nz = k1 * c * zr - 1.0;
    if (s->conic != 0) {
        vd inv = one / K(vsqrt)(H->nx * H->nx + H->ny * H->ny + H->nz * H->nz);
        H->nx *= inv, H->ny *= inv, H->nz *= inv;
    }
    H->inside = H->px * H->px + H->py * H->py <= sd2;
}

/* The hit of an even asphere: the safeguarded scalar solver, lane by lane. */
KATTR VINLINE void K(asphere_hit)(const lens_surface *s, double vz, double sd2, vd n1, vd n2,
                                  const K(rays) *R, K(hit) *H)
{
    for (int l = 0; l < KW; l++) {
        double o[3] = {R->ox[l], R->oy[l], R->oz[l]}, d[3] = {R->dx[l], R->dy[l], R->dz[l]},
               tt = 0, p[3] = {0, 0, 0}, nn[3] = {0, 0, -1};
        isect_status is = R->alive[l] ? intersect_surface(s, vz, o, d, sd2, &tt, p, nn)
                                      : ISECT_MISS;
        H->hit[l] = is != ISECT_MISS ? -1 : 0;
        H->inside[l] = is == ISECT_HIT ? -1 : 0;
        H->t[l] = tt, H->px[l] = p[0], H->py[l] = p[1], H->pz[l] = p[2];
        H->nx[l] = nn[0], H->ny[l] = nn[1], H->nz[l] = nn[2];
    }
    H->e = n1 / n2;
}

/* Refraction at the hit for the lanes in ok (Snell, the normal turned against the ray),
 * and their transmittance times the unpolarised Fresnel factor; returns the lanes with
 * total internal reflection. */
KATTR VINLINE vi K(refract)(vd n1, vd n2, vi ok, K(hit) *H, K(rays) *R)
{
    const vd one = K(vsplat)(1.0), zero = K(vsplat)(0.0);
    vd e = H->e;
    vd cosi = -(R->dx * H->nx + R->dy * H->ny + R->dz * H->nz);
    vi flip = cosi < zero;
    H->nx = K(vsel)(flip, -H->nx, H->nx), H->ny = K(vsel)(flip, -H->ny, H->ny);
    H->nz = K(vsel)(flip, -H->nz, H->nz);
    cosi = K(vabs)(cosi);
    vd k = one - e * e * (one - cosi * cosi);
    vi tir = k < zero;
    vd cost = K(vsqrt)(K(vsel)(tir, zero, k));
    vd m = e * cosi - cost;
    vi upd = ok & ~tir;
    R->dx = K(vsel)(upd, e * R->dx + m * H->nx, R->dx);
    R->dy = K(vsel)(upd, e * R->dy + m * H->ny, R->dy);
    R->dz = K(vsel)(upd, e * R->dz + m * H->nz, R->dz);
    /* Unpolarised Fresnel, 1 - (rs^2 + rp^2)/2 over one common denominator. */
    vd a = n1 * cosi, b = n2 * cost, cc = n2 * cosi, f = n1 * cost;
    vd sp = a + b, sm = a - b, pp = f + cc, pm = f - cc;
    vd den = sp * sp * pp * pp;
    vd T = one - 0.5 * (sm * sm * pp * pp + pm * pm * sp * sp) / den;
    T = K(vsel)((den > zero) & (T > zero), T, zero); /* 1 - R rounds below 0 as R -> 1 */
    R->eta = K(vsel)(upd, R->eta * T, R->eta);
    return tir;
}

/* Writes the lanes back: rays, status, transmittance, and (outer, when traced to the
 * front) the outer-pupil coordinates in the frame (fx, 0, fz), (gx, gy, gz). */
KATTR VINLINE void K(store)(int count, const K(rays) *R, const int status[KW],
                            const int surface[KW], vd fx, vd fy, vd fz, vd gx, vd gy,
                            vd gz, lens_ray *r, trace_result *res, double *outer)
{
    if (outer) {
        vd u = R->dx * fx + R->dy * fy + R->dz * fz, v = R->dx * gx + R->dy * gy + R->dz * gz;
        for (int l = 0; l < count; l++) { /* only passed rays have a defined frame */
            int p = status[l] == TRACE_PASSED;
            outer[4 * l] = p ? R->ox[l] : NAN, outer[4 * l + 1] = p ? R->oy[l] : NAN;
            outer[4 * l + 2] = p ? u[l] : NAN, outer[4 * l + 3] = p ? v[l] : NAN;
        }
    }
    for (int l = 0; l < count; l++) {
        r[l].o[0] = R->ox[l], r[l].o[1] = R->oy[l], r[l].o[2] = R->oz[l];
        r[l].d[0] = R->dx[l], r[l].d[1] = R->dy[l], r[l].d[2] = R->dz[l];
        res[l].status = (trace_status)status[l];
        res[l].surface = surface[l];
        res[l].transmittance = status[l] == TRACE_PASSED ? R->eta[l] : 0.0;
    }
}

KATTR static void KNAME(const lens_t *lens, const double *const *n, int count, lens_ray *r,
                        int last, trace_result *res, double *outer)
{
    K(rays) R;
    const double *nl[KW];
    int status[KW], surface[KW];
    K(load)(lens, n, count, r, &R, nl, status, surface);
    const vd one = K(vsplat)(1.0), zero = K(vsplat)(0.0);
    vd fx = zero, fy = zero, fz = zero, gx = zero, gy = zero, gz = zero; /* outer frame */
    /* The lanes' indices, surface by surface, as vectors (transposed once). */
    vd nv[lens->nsurf];
    for (size_t i = 0; i < lens->nsurf; i++)
        for (int l = 0; l < KW; l++)
            nv[i][l] = nl[l][i];
    for (int i = (int)lens->nsurf - 1; i >= last && K(vany)(R.alive); i--) {
        const lens_surface *s = &lens->surf[i];
        double c = isfinite(s->radius) ? 1.0 / s->radius : 0.0, k1 = 1.0 + s->conic;
        double vz = lens->vertex_z[i], sd2 = s->semi_diameter * s->semi_diameter;
        /* From n[i] (sensor side) into n[i-1] (object side). */
        vd n1 = nv[i], n2 = i > 0 ? nv[i - 1] : one;
        int asph = 0;
        for (int k = 0; k < LENS_ASPHERE_TERMS; k++)
            asph |= s->asphere[k] != 0;
        K(hit) H;
        if (!asph)
            K(conic_hit)(s, c, k1, vz, sd2, n1, n2, &R, &H);
        else
            K(asphere_hit)(s, vz, sd2, n1, n2, &R, &H);
        vi ok = R.alive & H.hit & H.inside;
        vi moved = R.alive & H.hit;
        R.ox = K(vsel)(moved, H.px, R.ox), R.oy = K(vsel)(moved, H.py, R.oy);
        R.oz = K(vsel)(moved, H.pz, R.oz);
        vi tir = (vi)zero;
        int refr = i > last || last == 0;
        if (i == 0 && outer) {
            /* The outer-pupil frame of trace.h from the front normal at the hit. */
            vd k = one / (one - H.nz);
            vd exy = -k * H.nx * H.ny;
            fx = one - k * H.nx * H.nx, fy = exy, fz = H.nx; /* applied after refraction */
            gx = exy, gy = one - k * H.ny * H.ny, gz = H.ny;
        }
        if (refr && K(vany)(n1 != n2))
            tir = K(refract)(n1, n2, ok, &H, &R);
        vi died = R.alive & ~(ok & ~tir);
        if (K(vany)(died)) {
            for (int l = 0; l < KW; l++)
                if (died[l]) {
                    surface[l] = i;
                    status[l] = !H.hit[l] ? TRACE_MISSED
                                : !H.inside[l] ? (i == lens->stop ? TRACE_STOPPED : TRACE_CLIPPED)
                                               : TRACE_TIR;
                }
            R.alive &= ~died;
        }
    }
    K(store)(count, &R, status, surface, fx, fy, fz, gx, gy, gz, r, res,
             outer && last == 0 ? outer : NULL);
}
