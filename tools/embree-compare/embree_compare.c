/* Embree 3 traces the rays raystep exported (`raystep bench SCENE --section rays --export FILE`)
 * and prints its rates beside raystep's answers checked: same hit mask, same mean t.
 *
 * Not part of raystep's build: it needs Debian's libembree-dev. See tools/embree-compare/README.md.
 *
 *   cc -O2 -o embree_compare embree_compare.c -lembree3 -lpthread -lm
 *   ./embree_compare FILE [--reps N] [--quality low|medium|high]
 *
 * File layout (little-endian, written by src/bench/throughput.rs): "RSEMBRT1", u32 triangles,
 * spheres, primary rays, shadow rays; triangles (9 f32); spheres (x, y, z, r); primary rays
 * (origin, direction); shadow rays (origin, direction, t_min, t_max); raystep's answers: per
 * primary ray a hit byte and t (f32), per shadow ray a blocked byte.
 */
#include <embree3/rtcore.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct {
  uint32_t tris, spheres, primary, shadow;
  float *tri, *sph, *prim, *shad;
  uint8_t *raystep_hit, *raystep_blocked;
  float *raystep_t;
} Set;

static void die(const char *what) {
  fprintf(stderr, "embree_compare: %s\n", what);
  exit(1);
}

static void *read_exact(FILE *f, size_t bytes) {
  void *p = malloc(bytes ? bytes : 1);
  if (!p) die("out of memory");
  if (bytes && fread(p, 1, bytes, f) != bytes) die("file ends early (not a complete export)");
  return p;
}

static Set load(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) die("cannot open the export file");
  char magic[8];
  if (fread(magic, 1, 8, f) != 8 || memcmp(magic, "RSEMBRT1", 8) != 0)
    die("not a raystep export (magic RSEMBRT1 missing)");
  Set s;
  uint32_t n[4];
  if (fread(n, 4, 4, f) != 4) die("file ends in the header");
  s.tris = n[0], s.spheres = n[1], s.primary = n[2], s.shadow = n[3];
  s.tri = read_exact(f, (size_t)s.tris * 9 * 4);
  s.sph = read_exact(f, (size_t)s.spheres * 4 * 4);
  s.prim = read_exact(f, (size_t)s.primary * 6 * 4);
  s.shad = read_exact(f, (size_t)s.shadow * 8 * 4);
  s.raystep_hit = malloc(s.primary ? s.primary : 1);
  s.raystep_t = malloc((size_t)(s.primary ? s.primary : 1) * 4);
  if (!s.raystep_hit || !s.raystep_t) die("out of memory");
  for (uint32_t i = 0; i < s.primary; i++) {
    unsigned char rec[5];
    if (fread(rec, 1, 5, f) != 5) die("file ends in raystep's answers");
    s.raystep_hit[i] = rec[0];
    memcpy(&s.raystep_t[i], rec + 1, 4);
  }
  s.raystep_blocked = read_exact(f, s.shadow);
  fclose(f);
  return s;
}

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

static RTCScene build(RTCDevice dev, const Set *s, enum RTCBuildQuality q, double *seconds) {
  double start = now();
  RTCScene scene = rtcNewScene(dev);
  rtcSetSceneBuildQuality(scene, q);
  if (s->tris) {
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(g, q);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), (size_t)s->tris * 3);
    unsigned *idx = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                            3 * sizeof(unsigned), s->tris);
    memcpy(v, s->tri, (size_t)s->tris * 9 * 4);
    for (unsigned i = 0; i < s->tris * 3; i++) idx[i] = i;
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
  }
  if (s->spheres) {
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    rtcSetGeometryBuildQuality(g, q);
    float *p = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                       4 * sizeof(float), s->spheres);
    memcpy(p, s->sph, (size_t)s->spheres * 16);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(scene);
  *seconds = now() - start;
  return scene;
}

typedef struct {
  RTCScene scene;
  const Set *s;
  int shadow;
  atomic_uint next;
  uint8_t *hit;
  float *t;
} Job;

enum { CHUNK = 4096 };

static void *work(void *arg) {
  Job *j = arg;
  uint32_t n = j->shadow ? j->s->shadow : j->s->primary;
  struct RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  for (;;) {
    uint32_t begin = atomic_fetch_add(&j->next, CHUNK);
    if (begin >= n) break;
    uint32_t end = begin + CHUNK < n ? begin + CHUNK : n;
    for (uint32_t i = begin; i < end; i++) {
      if (j->shadow) {
        const float *r = j->s->shad + (size_t)i * 8;
        struct RTCRay ray = {r[0], r[1], r[2], r[6], r[3], r[4], r[5], 0.0f, r[7], -1u, 0, 0};
        rtcOccluded1(j->scene, &ctx, &ray);
        j->hit[i] = ray.tfar == -INFINITY;
      } else {
        const float *r = j->s->prim + (size_t)i * 6;
        struct RTCRayHit rh;
        rh.ray = (struct RTCRay){r[0], r[1], r[2], 0.0f, r[3], r[4], r[5], 0.0f, INFINITY, -1u, 0, 0};
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(j->scene, &ctx, &rh);
        j->hit[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        j->t[i] = rh.ray.tfar;
      }
    }
  }
  return NULL;
}

/* One pass over the primary (shadow) rays on `threads` threads; returns seconds. */
static double pass(RTCScene scene, const Set *s, int shadow, int threads, uint8_t *hit, float *t) {
  Job j = {scene, s, shadow, 0, hit, t};
  pthread_t th[64];
  double start = now();
  for (int i = 1; i < threads; i++) pthread_create(&th[i], NULL, work, &j);
  work(&j);
  for (int i = 1; i < threads; i++) pthread_join(th[i], NULL);
  return now() - start;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(RTCScene scene, const Set *s, int shadow, int threads, int reps, uint8_t *hit,
                     float *t) {
  double times[101];
  for (int r = 0; r < reps; r++) times[r] = pass(scene, s, shadow, threads, hit, t);
  qsort(times, reps, sizeof(double), cmp_double);
  return times[reps / 2];
}

int main(int argc, char **argv) {
  if (argc < 2)
    die("usage: embree_compare FILE [--reps N] [--quality low|medium|high] [--config STRING]");
  int reps = 5;
  /* Embree's device configuration, e.g. "isa=avx2" to keep it to the ISA raystep uses, or
     "verbose=1" to print the ISA it chose (Embree's rtcNewDevice documentation). */
  const char *config = NULL;
  enum RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM;
  const char *qname = "medium";
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!strcmp(argv[i], "--reps")) {
      reps = atoi(argv[i + 1]);
      if (reps < 1 || reps > 101) die("--reps must be 1 to 101");
    } else if (!strcmp(argv[i], "--quality")) {
      qname = argv[i + 1];
      if (!strcmp(qname, "low")) quality = RTC_BUILD_QUALITY_LOW;
      else if (!strcmp(qname, "medium")) quality = RTC_BUILD_QUALITY_MEDIUM;
      else if (!strcmp(qname, "high")) quality = RTC_BUILD_QUALITY_HIGH;
      else die("--quality must be low, medium or high");
    } else if (!strcmp(argv[i], "--config")) {
      config = argv[i + 1];
    } else {
      die("unknown option");
    }
  }
  Set s = load(argv[1]);
  RTCDevice dev = rtcNewDevice(config);
  if (!dev) die("rtcNewDevice failed (a --config Embree does not accept?)");
  double build_s;
  RTCScene scene = build(dev, &s, quality, &build_s);
  uint8_t *hit = calloc(s.primary + 1, 1), *blocked = calloc(s.shadow + 1, 1);
  float *t = calloc(s.primary + 1, 4);
  if (!hit || !blocked || !t) die("out of memory");

  double p1 = median(scene, &s, 0, 1, reps, hit, t);
  double p2 = median(scene, &s, 0, 2, reps, hit, t);
  double s1 = median(scene, &s, 1, 1, reps, blocked, NULL);
  double s2 = median(scene, &s, 1, 2, reps, blocked, NULL);

  /* The answers against raystep's. */
  uint32_t hits = 0, mask_diff = 0, blocked_n = 0, blocked_diff = 0;
  double t_sum = 0, raystep_t_sum = 0, max_rel = 0;
  for (uint32_t i = 0; i < s.primary; i++) {
    mask_diff += hit[i] != s.raystep_hit[i];
    if (hit[i]) hits++, t_sum += t[i];
    if (s.raystep_hit[i]) raystep_t_sum += s.raystep_t[i];
    if (hit[i] && s.raystep_hit[i]) {
      double rel = fabs((double)t[i] - s.raystep_t[i]) / fmax(1e-30, fabs(s.raystep_t[i]));
      if (rel > max_rel) max_rel = rel;
    }
  }
  uint32_t raystep_hits = 0;
  for (uint32_t i = 0; i < s.primary; i++) raystep_hits += s.raystep_hit[i];
  for (uint32_t i = 0; i < s.shadow; i++) {
    blocked_n += blocked[i];
    blocked_diff += blocked[i] != s.raystep_blocked[i];
  }
  printf("Embree %d.%d.%d, %s build: %.0f ms; %u triangles, %u spheres\n", RTC_VERSION_MAJOR,
         RTC_VERSION_MINOR, RTC_VERSION_PATCH, qname, build_s * 1e3, s.tris, s.spheres);
  printf("- primary: %u hits (raystep %u, %u rays differ), mean t %.6f (raystep %.6f), largest "
         "relative t difference %.2e\n",
         hits, raystep_hits, mask_diff, t_sum / (hits ? hits : 1),
         raystep_t_sum / (raystep_hits ? raystep_hits : 1), max_rel);
  printf("- primary: 1 thread %.2f Mrays/s, 2 threads %.2f Mrays/s (%.2fx)\n",
         s.primary / p1 / 1e6, s.primary / p2 / 1e6, p1 / p2);
  printf("- shadow: %u blocked (%u rays differ); 1 thread %.2f Mrays/s, 2 threads %.2f Mrays/s "
         "(%.2fx)\n",
         blocked_n, blocked_diff, s.shadow / s1 / 1e6, s.shadow / s2 / 1e6, s1 / s2);
  rtcReleaseScene(scene);
  rtcReleaseDevice(dev);
  return 0;
}
