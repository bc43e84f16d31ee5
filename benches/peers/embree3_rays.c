/* Embree 3 (Debian's libembree-dev), called from C: the native speed of the rays
 * embree_rays.py dumps, without a Python binding's per-ray cost.
 *
 *   embree3_rays MODEL.obj RAYS_DIR [RUNS]
 *
 * Reads the mesh (OBJ `v` and `f` lines, polygons fanned) and RAYS_DIR/primary.rays,
 * shadow.rays and random.rays (56-byte records of little-endian f64: origin xyz,
 * direction xyz, t_max), builds one scene (default build quality, as a static scene
 * gets by default), and traces every file
 *   single:  one ray a call (rtcIntersect1; shadow.rays: rtcOccluded1),
 *   packet8: 8 consecutive rays a call (rtcIntersect8 / rtcOccluded8, coherent context
 *            flag; for primary rays these are 8 neighbouring pixels of a row),
 * on 1 and 2 POSIX threads (chunks of 1024 rays handed out by an atomic counter).
 * Prints one JSON line: build time (median of RUNS builds on a warm device), and for
 * each file the rays, hits (occluded for shadow rays) and median Mrays/s of RUNS runs
 * after a warm-up.  Built and run by embree3_rays.sh.
 */
#define _POSIX_C_SOURCE 200809L
#include <embree3/rtcore.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void die(const char *what, const char *detail) {
    fprintf(stderr, "embree3_rays: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    exit(1);
}

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- mesh ---- */

typedef struct {
    float *v;      /* xyz a vertex */
    unsigned *t;   /* three indices a triangle */
    size_t nv, nt, cap_v, cap_t;
} Mesh;

static void push_v(Mesh *m, float x, float y, float z) {
    if (m->nv == m->cap_v) {
        m->cap_v = m->cap_v ? 2 * m->cap_v : 1024;
        m->v = realloc(m->v, 3 * m->cap_v * sizeof(float));
        if (!m->v) die("out of memory", NULL);
    }
    m->v[3 * m->nv] = x, m->v[3 * m->nv + 1] = y, m->v[3 * m->nv + 2] = z;
    m->nv++;
}

static void push_t(Mesh *m, unsigned a, unsigned b, unsigned c) {
    if (m->nt == m->cap_t) {
        m->cap_t = m->cap_t ? 2 * m->cap_t : 1024;
        m->t = realloc(m->t, 3 * m->cap_t * sizeof(unsigned));
        if (!m->t) die("out of memory", NULL);
    }
    m->t[3 * m->nt] = a, m->t[3 * m->nt + 1] = b, m->t[3 * m->nt + 2] = c;
    m->nt++;
}

static Mesh load_obj(const char *path) {
    Mesh m = {0};
    FILE *f = fopen(path, "r");
    if (!f) die("cannot open", path);
    char line[4096];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == 'v' && line[1] == ' ') {
            float x, y, z;
            if (sscanf(line + 2, "%f %f %f", &x, &y, &z) != 3) die("bad vertex line in", path);
            push_v(&m, x, y, z);
        } else if (line[0] == 'f' && line[1] == ' ') {
            long idx[64];
            int n = 0;
            char *p = line + 2;
            while (n < 64) {
                char *end;
                long i = strtol(p, &end, 10);
                if (end == p) break;
                idx[n++] = i > 0 ? i - 1 : (long)m.nv + i;
                p = end;
                while (*p && *p != ' ' && *p != '\t' && *p != '\n' && *p != '\r') p++; /* skip /vt/vn */
            }
            for (int k = 1; k + 1 < n; k++) push_t(&m, (unsigned)idx[0], (unsigned)idx[k], (unsigned)idx[k + 1]);
        }
    }
    fclose(f);
    if (m.nt == 0) die("no triangles in", path);
    for (size_t i = 0; i < 3 * m.nt; i++)
        if (m.t[i] >= m.nv) die("face index out of range in", path);
    return m;
}

/* ---- rays ---- */

typedef struct {
    float *ox, *oy, *oz, *dx, *dy, *dz, *tmax;
    size_t n;
} Rays;

static int load_rays(const char *path, Rays *r) {
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    fseek(f, 0, SEEK_END);
    long bytes = ftell(f);
    fseek(f, 0, SEEK_SET);
    if (bytes < 0 || bytes % 56) die("not a whole number of 56-byte rays", path);
    r->n = (size_t)bytes / 56;
    double *buf = malloc((size_t)bytes + 1);
    if (!buf || fread(buf, 1, (size_t)bytes, f) != (size_t)bytes) die("cannot read", path);
    fclose(f);
    float **cols[7] = {&r->ox, &r->oy, &r->oz, &r->dx, &r->dy, &r->dz, &r->tmax};
    for (int c = 0; c < 7; c++) {
        *cols[c] = malloc((r->n + 8) * sizeof(float));
        for (size_t i = 0; i < r->n; i++) (*cols[c])[i] = (float)buf[7 * i + c]; /* x86: little-endian */
    }
    free(buf);
    return 1;
}

/* ---- tracing ---- */

enum { CHUNK = 1024 };

typedef struct {
    RTCScene scene;
    const Rays *rays;
    int occlusion, packet;
    atomic_size_t next;
} Job;

typedef struct {
    Job *job;
    size_t hits;
} Worker;

static size_t trace_range(const Job *job, size_t begin, size_t end) {
    const Rays *r = job->rays;
    size_t hits = 0;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    if (!job->packet) {
        for (size_t i = begin; i < end; i++) {
            struct RTCRayHit rh;
            rh.ray.org_x = r->ox[i], rh.ray.org_y = r->oy[i], rh.ray.org_z = r->oz[i];
            rh.ray.dir_x = r->dx[i], rh.ray.dir_y = r->dy[i], rh.ray.dir_z = r->dz[i];
            rh.ray.tnear = 0.0f, rh.ray.tfar = r->tmax[i], rh.ray.time = 0.0f;
            rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
            if (job->occlusion) {
                rtcOccluded1(job->scene, &ctx, &rh.ray);
                hits += rh.ray.tfar == -INFINITY;
            } else {
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID, rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(job->scene, &ctx, &rh);
                hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
        }
        return hits;
    }
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (size_t i = begin; i < end; i += 8) {
        struct RTCRayHit8 rh;
        int valid[8];
        for (int k = 0; k < 8; k++) {
            size_t j = i + (size_t)k;
            valid[k] = j < end ? -1 : 0;
            if (j >= end) j = begin; /* inactive lanes still get finite values */
            rh.ray.org_x[k] = r->ox[j], rh.ray.org_y[k] = r->oy[j], rh.ray.org_z[k] = r->oz[j];
            rh.ray.dir_x[k] = r->dx[j], rh.ray.dir_y[k] = r->dy[j], rh.ray.dir_z[k] = r->dz[j];
            rh.ray.tnear[k] = 0.0f, rh.ray.tfar[k] = r->tmax[j], rh.ray.time[k] = 0.0f;
            rh.ray.mask[k] = 0xFFFFFFFFu, rh.ray.id[k] = 0, rh.ray.flags[k] = 0;
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID, rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        if (job->occlusion) {
            rtcOccluded8(valid, job->scene, &ctx, &rh.ray);
            for (int k = 0; k < 8; k++) hits += valid[k] && rh.ray.tfar[k] == -INFINITY;
        } else {
            rtcIntersect8(valid, job->scene, &ctx, &rh);
            for (int k = 0; k < 8; k++) hits += valid[k] && rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        }
    }
    return hits;
}

static void *work(void *arg) {
    Worker *w = arg;
    Job *job = w->job;
    size_t n = job->rays->n;
    for (;;) {
        size_t begin = atomic_fetch_add(&job->next, CHUNK);
        if (begin >= n) break;
        size_t end = begin + CHUNK < n ? begin + CHUNK : n;
        w->hits += trace_range(job, begin, end);
    }
    return NULL;
}

/* Seconds for one pass over the rays on `threads` threads; their hits in *hits. */
static double run(RTCScene scene, const Rays *rays, int occlusion, int packet, int threads, size_t *hits) {
    Job job = {scene, rays, occlusion, packet, 0};
    Worker w[2] = {{&job, 0}, {&job, 0}};
    pthread_t tid[2];
    double start = now_s();
    for (int k = 1; k < threads; k++) pthread_create(&tid[k], NULL, work, &w[k]);
    work(&w[0]);
    for (int k = 1; k < threads; k++) pthread_join(tid[k], NULL);
    double secs = now_s() - start;
    *hits = w[0].hits + w[1].hits;
    return secs;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *xs, int n) {
    qsort(xs, (size_t)n, sizeof *xs, cmp_double);
    return n % 2 ? xs[n / 2] : 0.5 * (xs[n / 2 - 1] + xs[n / 2]);
}

static RTCScene build(RTCDevice dev, const Mesh *m) {
    RTCScene scene = rtcNewScene(dev);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m->nv);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m->nt);
    memcpy(vb, m->v, 3 * m->nv * sizeof(float));
    memcpy(ib, m->t, 3 * m->nt * sizeof(unsigned));
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    return scene;
}

int main(int argc, char **argv) {
    if (argc < 3 || argc > 4) die("usage: embree3_rays MODEL.obj RAYS_DIR [RUNS]", NULL);
    int runs = argc == 4 ? atoi(argv[3]) : 5;
    if (runs < 1 || runs > 100) die("RUNS must be 1 to 100", NULL);
    Mesh mesh = load_obj(argv[1]);

    RTCDevice dev = rtcNewDevice(NULL);
    if (!dev) die("rtcNewDevice failed", NULL);
    rtcReleaseScene(build(dev, &mesh)); /* warm-up: the thread pool starts */
    double builds[100];
    RTCScene scene = NULL;
    for (int k = 0; k < runs; k++) {
        if (scene) rtcReleaseScene(scene);
        double start = now_s();
        scene = build(dev, &mesh);
        builds[k] = now_s() - start;
    }

    const char *base = strrchr(argv[1], '/');
    printf("{\"peer\": \"embree3-c\", \"embree\": \"%ld.%ld.%ld\", \"model\": \"%s\", \"triangles\": %zu, "
           "\"build_ms\": %.3f, \"native_ray8\": %ld, \"native_ray16\": %ld, \"runs\": %d, "
           "\"parallel\": \"POSIX threads, chunks of %d rays\"",
           rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_VERSION_MAJOR),
           rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_VERSION_MINOR),
           rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_VERSION_PATCH), base ? base + 1 : argv[1], mesh.nt,
           1e3 * median(builds, runs), rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED),
           rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED), runs, CHUNK);

    const char *kinds[3] = {"primary", "shadow", "random"};
    int found = 0;
    for (int k = 0; k < 3; k++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s.rays", argv[2], kinds[k]);
        Rays rays;
        if (!load_rays(path, &rays)) continue;
        found++;
        int occlusion = k == 1;
        printf(", \"%s\": {\"rays\": %zu", kinds[k], rays.n);
        size_t first_hits = 0;
        for (int packet = 0; packet < 2; packet++) {
            for (int threads = 1; threads <= 2; threads++) {
                double secs[101];
                size_t hits = 0;
                for (int r = 0; r <= runs; r++) secs[r] = run(scene, &rays, occlusion, packet, threads, &hits);
                if (packet == 0 && threads == 1) {
                    first_hits = hits;
                    printf(", \"%s\": %zu", occlusion ? "occluded" : "hits", hits);
                } else if (hits != first_hits) {
                    fprintf(stderr, "embree3_rays: %s: %zu hits, not %zu\n", kinds[k], hits, first_hits);
                    return 1;
                }
                double med = median(secs + 1, runs); /* secs[0] was the warm-up */
                printf(", \"%s_mrays_per_s_%d\": %.4f", packet ? "packet8" : "single", threads, rays.n / med / 1e6);
            }
        }
        printf("}");
        fflush(stdout);
    }
    printf("}\n");
    if (!found) die("no primary.rays, shadow.rays or random.rays in", argv[2]);
    rtcReleaseScene(scene);
    rtcReleaseDevice(dev);
    return 0;
}
