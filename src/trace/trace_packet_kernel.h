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

KATTR static void KNAME(const lens_t *lens, const double *const *n, int count, lens_ray *r,
                        int last, trace_result *res, double *outer)
{
    vd ox, oy, oz, dx, dy, dz, eta = K(vsplat)(1.0);
    vi alive;
    /* Pad unused lanes with copies of lane 0 so they compute harmless numbers. */
    const double *nl[KW];
    for (int l = 0; l < KW; l++) {
        int s = l < count ? l : 0;
        ox[l] = r[s].o[0], oy[l] = r[s].o[1], oz[l] = r[s].o[2];
        dx[l] = r[s].d[0], dy[l] = r[s].d[1], dz[l] = r[s].d[2];
        nl[l] = n[s];
    }
    alive = K(visfinite)(ox) & K(visfinite)(oy) & K(visfinite)(oz) & K(visfinite)(dx) & K(visfinite)(dy) &
            K(visfinite)(dz);
    int status[KW], surface[KW];
    for (int l = 0; l < KW; l++) {
        status[l] = alive[l] ? TRACE_PASSED : TRACE_INVALID;
        surface[l] = alive[l] ? -1 : (int)lens->nsurf - 1;
    }
    const vd one = K(vsplat)(1.0), zero = K(vsplat)(0.0);
    vd fx = zero, fy = zero, fz = zero, gx = zero, gy = zero, gz = zero; /* outer frame */
    /* The lanes' indices, surface by surface, as vectors (transposed once). */
    vd nv[lens->nsurf];
    for (size_t i = 0; i < lens->nsurf; i++)
        for (int l = 0; l < KW; l++)
            nv[i][l] = nl[l][i];
    for (int i = (int)lens->nsurf - 1; i >= last && K(vany)(alive); i--) {
        const lens_surface *s = &lens->surf[i];
        double c = isfinite(s->radius) ? 1.0 / s->radius : 0.0, k1 = 1.0 + s->conic;
        double vz = lens->vertex_z[i], sd2 = s->semi_diameter * s->semi_diameter;
        vd t, px, py, pz, nx, ny, nz, e;
        vi hit, inside;
        /* From n[i] (sensor side) into n[i-1] (object side). */
        vd n1 = nv[i], n2 = i > 0 ? nv[i - 1] : one;
        int asph = 0;
        for (int k = 0; k < LENS_ASPHERE_TERMS; k++)
            asph |= s->asphere[k] != 0;
        if (!asph) {
            /* c (x^2 + y^2 + k1 z^2) - 2 z = 0 along the ray (intersect.c, vectorised) */
            vd qz = oz - vz;
            vd A = c * (dx * dx + dy * dy + k1 * dz * dz);
            vd B = c * (ox * dx + oy * dy + k1 * qz * dz) - dz;
            vd C = c * (ox * ox + oy * oy + k1 * qz * qz) - 2.0 * qz;
            vd disc = B * B - A * C;
            vi dok = disc >= zero;
            vd sq = K(vsqrt)(K(vsel)(dok, disc, zero));
            vd qq = -(B + K(vcopysign)(sq, B));
            /* The near root C / qq and the index ratio n1 / n2 share one division (the
             * divider is the bottleneck); the far root qq / A needs none for a sphere,
             * where A = c |d|^2 = c. qq = 0 only for a ray tangent at its own origin. */
            vi qnz = qq != zero;
            vd qs = K(vsel)(qnz, qq, one);
            vd inv = one / (qs * n2);
            vd r0 = C * n2 * inv, r1 = s->conic == 0 ? qq * s->radius : qq / A;
            e = n1 * qs * inv;
            vd z0 = qz + r0 * dz, z1 = qz + r1 * dz;
            vd lim = K(vsplat)(1.0 + 1e-12), tmin = K(vsplat)(ISECT_T_MIN);
            vi v0 = dok & qnz & K(visfinite)(r0) & (r0 > tmin) & (k1 * c * z0 <= lim);
            vi v1 = dok & K(visfinite)(r1) & (r1 > tmin) & (k1 * c * z1 <= lim);
            t = K(vsel)(v0 & v1, K(vsel)(r0 < r1, r0, r1), K(vsel)(v0, r0, r1));
            hit = v0 | v1;
            px = ox + t * dx, py = oy + t * dy;
            vd zr = qz + t * dz;
            pz = zr + vz;
            nx = c * px, ny = c * py, nz = k1 * c * zr - 1.0;
            if (s->conic != 0) {
                vd inv = one / K(vsqrt)(nx * nx + ny * ny + nz * nz);
                nx *= inv, ny *= inv, nz *= inv;
            }
            inside = px * px + py * py <= sd2;
        } else {
            /* Even asphere: the safeguarded scalar solver, lane by lane. */
            for (int l = 0; l < KW; l++) {
                double o[3] = {ox[l], oy[l], oz[l]}, d[3] = {dx[l], dy[l], dz[l]}, tt = 0,
                       p[3] = {0, 0, 0}, nn[3] = {0, 0, -1};
                isect_status is = alive[l] ? intersect_surface(s, vz, o, d, sd2, &tt, p, nn)
                                           : ISECT_MISS;
                hit[l] = is != ISECT_MISS ? -1 : 0;
                inside[l] = is == ISECT_HIT ? -1 : 0;
                t[l] = tt, px[l] = p[0], py[l] = p[1], pz[l] = p[2];
                nx[l] = nn[0], ny[l] = nn[1], nz[l] = nn[2];
            }
            e = n1 / n2;
        }
        vi ok = alive & hit & inside;
        vi moved = alive & hit;
        ox = K(vsel)(moved, px, ox), oy = K(vsel)(moved, py, oy), oz = K(vsel)(moved, pz, oz);
        vi tir = (vi)zero;
        int refr = i > last || last == 0;
        if (i == 0 && outer) {
            /* The outer-pupil frame of trace.h from the front normal at the hit. */
            vd k = one / (one - nz);
            vd exy = -k * nx * ny;
            fx = one - k * nx * nx, fy = exy, fz = nx; /* applied after refraction */
            gx = exy, gy = one - k * ny * ny, gz = ny;
        }
        if (refr) {
            if (K(vany)(n1 != n2)) {
                vd cosi = -(dx * nx + dy * ny + dz * nz);
                vi flip = cosi < zero;
                nx = K(vsel)(flip, -nx, nx), ny = K(vsel)(flip, -ny, ny), nz = K(vsel)(flip, -nz, nz);
                cosi = K(vabs)(cosi);
                vd k = one - e * e * (one - cosi * cosi);
                tir = k < zero;
                vd cost = K(vsqrt)(K(vsel)(tir, zero, k));
                vd m = e * cosi - cost;
                vi upd = ok & ~tir;
                dx = K(vsel)(upd, e * dx + m * nx, dx);
                dy = K(vsel)(upd, e * dy + m * ny, dy);
                dz = K(vsel)(upd, e * dz + m * nz, dz);
                /* Unpolarised Fresnel, 1 - (rs^2 + rp^2)/2 over one common denominator. */
                vd a = n1 * cosi, b = n2 * cost, cc = n2 * cosi, f = n1 * cost;
                vd sp = a + b, sm = a - b, pp = f + cc, pm = f - cc;
                vd den = sp * sp * pp * pp;
                vd T = one - 0.5 * (sm * sm * pp * pp + pm * pm * sp * sp) / den;
                T = K(vsel)((den > zero) & (T > zero), T, zero); /* 1 - R rounds below 0 as R -> 1 */
                eta = K(vsel)(upd, eta * T, eta);
            }
        }
        vi died = alive & ~(ok & ~tir);
        if (K(vany)(died)) {
            for (int l = 0; l < KW; l++)
                if (died[l]) {
                    surface[l] = i;
                    status[l] = !hit[l] ? TRACE_MISSED
                                : !inside[l] ? (i == lens->stop ? TRACE_STOPPED : TRACE_CLIPPED)
                                             : TRACE_TIR;
                }
            alive &= ~died;
        }
    }
    if (outer && last == 0) {
        vd u = dx * fx + dy * fy + dz * fz, v = dx * gx + dy * gy + dz * gz;
        for (int l = 0; l < count; l++) { /* only passed rays have a defined frame */
            int p = status[l] == TRACE_PASSED;
            outer[4 * l] = p ? ox[l] : NAN, outer[4 * l + 1] = p ? oy[l] : NAN;
            outer[4 * l + 2] = p ? u[l] : NAN, outer[4 * l + 3] = p ? v[l] : NAN;
        }
    }
    for (int l = 0; l < count; l++) {
        r[l].o[0] = ox[l], r[l].o[1] = oy[l], r[l].o[2] = oz[l];
        r[l].d[0] = dx[l], r[l].d[1] = dy[l], r[l].d[2] = dz[l];
        res[l].status = (trace_status)status[l];
        res[l].surface = surface[l];
        res[l].transmittance = status[l] == TRACE_PASSED ? eta[l] : 0.0;
    }
}

#undef vd
#undef vi
