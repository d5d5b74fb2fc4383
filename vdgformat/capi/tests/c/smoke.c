/*
 * smoke.c: proves libvdg from C. Compiled and run by tests/c_smoke.rs, which
 * writes the script, runs the same script through the Rust API and compares
 * this program's output with it byte for byte (floats are printed as their
 * bit patterns, so "equal" means bit-identical).
 *
 * usage: smoke GRAPH.vdg SCRIPT CORRUPT.vdg [REPEAT]
 *
 * SCRIPT lines (floats as 8 hex digits of their IEEE-754 bits):
 *   Q ax ay az bx by bz radius          a query pair
 *   T ox oy oz pitch yaw roll vx vy vz dt   one camera frame's target
 *
 * With REPEAT > 0 the camera frames are replayed REPEAT more times with a
 * fresh camera and the median time per frame goes to stderr.
 */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "vdg.h"

#define MAX_QUERIES 256
#define MAX_FRAMES 4096
#define PATH_POINTS 8 /* small on purpose: long paths take the "needed size" route */

typedef struct {
    float a[3], b[3], radius;
} query;

static query queries[MAX_QUERIES];
static vdg_target targets[MAX_FRAMES];
static float dts[MAX_FRAMES];
static int n_queries, n_frames;

static uint32_t bits(float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static float unbits(uint32_t u) {
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static void die(const char *what) {
    fprintf(stderr, "smoke: %s: %s\n", what, vdg_last_error());
    exit(2);
}

static int read_floats(FILE *f, float *out, int n) {
    for (int i = 0; i < n; i++) {
        unsigned int u;
        if (fscanf(f, "%x", &u) != 1)
            return 0;
        out[i] = unbits((uint32_t)u);
    }
    return 1;
}

static void read_script(const char *path) {
    FILE *f = fopen(path, "r");
    char kind[4];
    if (!f) {
        perror(path);
        exit(2);
    }
    while (fscanf(f, "%3s", kind) == 1) {
        if (kind[0] == 'Q' && n_queries < MAX_QUERIES) {
            query *q = &queries[n_queries++];
            float v[7];
            if (!read_floats(f, v, 7))
                break;
            memcpy(q->a, v, sizeof q->a);
            memcpy(q->b, v + 3, sizeof q->b);
            q->radius = v[6];
        } else if (kind[0] == 'T' && n_frames < MAX_FRAMES) {
            float v[10];
            if (!read_floats(f, v, 10))
                break;
            memcpy(targets[n_frames].origin, v, 3 * sizeof(float));
            memcpy(targets[n_frames].angles, v + 3, 3 * sizeof(float));
            memcpy(targets[n_frames].velocity, v + 6, 3 * sizeof(float));
            dts[n_frames++] = v[9];
        } else {
            fprintf(stderr, "smoke: bad script line kind '%s'\n", kind);
            exit(2);
        }
    }
    fclose(f);
}

static unsigned char *read_file(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    unsigned char *data;
    long n;
    if (!f || fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        perror(path);
        exit(2);
    }
    data = malloc((size_t)n + 1);
    if (!data || fread(data, 1, (size_t)n, f) != (size_t)n) {
        perror(path);
        exit(2);
    }
    fclose(f);
    *len = (size_t)n;
    return data;
}

static void print_pose(const vdg_pose *p) {
    printf("%08x %08x %08x %08x %08x %08x %d %d %08x %08x %08x %d %d", bits(p->origin[0]),
           bits(p->origin[1]), bits(p->origin[2]), bits(p->angles[0]), bits(p->angles[1]),
           bits(p->angles[2]), p->cut, p->target_visible, bits(p->look_at[0]),
           bits(p->look_at[1]), bits(p->look_at[2]), p->status, p->face);
}

static void run_queries(const char *label, const vdg_graph *g) {
    vdg_info info;
    if (vdg_get_info(g, &info) != VDG_OK)
        die("vdg_get_info");
    printf("%s info %u %u %016llx %08x\n", label, info.vertex_count, info.face_count,
           (unsigned long long)info.source_hash, bits(info.max_clearance));
    for (int i = 0; i < n_queries; i++) {
        const query *q = &queries[i];
        float points[3 * PATH_POINTS], length = -1.0f;
        intptr_t n = vdg_path(g, q->a, q->b, q->radius, points, PATH_POINTS, &length);
        printf("%s Q %08x %d %08x %ld %08x", label, bits(vdg_clearance(g, q->a)),
               vdg_visible(g, q->a, q->b), bits(vdg_vdistance(g, q->a, q->b)), (long)n,
               n > 0 ? bits(length) : 0u);
        if (n > PATH_POINTS) {
            /* Too small: the call said how much it needs. Ask again. */
            float *all = malloc(3 * sizeof(float) * (size_t)n);
            if (!all || vdg_path(g, q->a, q->b, q->radius, all, (size_t)n, NULL) != n)
                die("vdg_path with the size it asked for");
            for (intptr_t k = 0; k < 3 * n; k++)
                printf(" %08x", bits(all[k]));
            free(all);
        } else {
            for (intptr_t k = 0; k < 3 * n; k++)
                printf(" %08x", bits(points[k]));
        }
        printf("\n");
    }
}

static void run_camera(const vdg_graph *g, const vdg_graph *other) {
    vdg_camera *cam = vdg_camera_new(g, NULL);
    vdg_pose pose;
    if (!cam)
        die("vdg_camera_new");
    for (int i = 0; i < n_frames; i++) {
        int rc = i == 0 ? vdg_camera_reset(cam, g, &targets[i], &pose)
                        : vdg_camera_update(cam, g, &targets[i], dts[i], &pose);
        if (rc != VDG_OK)
            die("vdg_camera_update");
        printf("C %d ", i);
        print_pose(&pose);
        printf("\n");
    }
    /* The same map opened again is another graph: the camera starts anew. */
    if (vdg_camera_update(cam, other, &targets[n_frames - 1], dts[n_frames - 1], &pose) != VDG_OK)
        die("vdg_camera_update on the other graph");
    printf("C other ");
    print_pose(&pose);
    printf("\n");
    vdg_camera_free(cam);
}

static void run_director(const vdg_graph *g) {
    vdg_director *d = vdg_director_new();
    vdg_pose pose;
    memset(&pose, 0, sizeof pose);
    vdg_event events[8];
    int a, b;
    if (!d)
        die("vdg_director_new");
    a = vdg_director_add_camera(d, NULL);
    b = vdg_director_add_camera(d, "distance_mu = 160.0\nangle_mu_yaw_deg = 90.0\n");
    if (a < 0 || b < 0)
        die("vdg_director_add_camera");
    printf("D cameras %d %d active %d\n", a, b, vdg_director_active(d));
    for (int i = 0; i < n_frames; i++) {
        intptr_t n;
        int rc;
        if (vdg_director_set_target(d, a, &targets[i]) != VDG_OK ||
            vdg_director_set_target(d, b, &targets[i]) != VDG_OK)
            die("vdg_director_set_target");
        if (i == n_frames / 2 && vdg_director_activate(d, b) != VDG_OK)
            die("vdg_director_activate");
        rc = vdg_director_update(d, g, dts[i], &pose);
        if (rc < 0)
            die("vdg_director_update");
        printf("D %d %d ", i, rc);
        print_pose(&pose);
        n = vdg_director_events(d, events, 8);
        printf(" events %ld", (long)n);
        for (intptr_t k = 0; k < n && k < 8; k++)
            printf(" %d:%d:%d", events[k].kind, events[k].camera, events[k].from);
        printf("\n");
    }
    vdg_director_free(d);
}

static void run_errors(const vdg_graph *g, const char *corrupt) {
    float p[3] = {0, 0, 0}, nan3[3] = {NAN, 0, 0}, fl;
    vdg_pose pose;
    intptr_t n;
    int rc;
    vdg_camera *cam;
    size_t len;
    unsigned char *bytes;
    vdg_graph *bad = vdg_open(corrupt);
    printf("E corrupt-open %s %s\n", bad ? "opened" : "NULL", vdg_last_error());
    vdg_close(bad);
    bytes = read_file(corrupt, &len);
    bad = vdg_open_memory(bytes, len);
    printf("E corrupt-memory %s %s\n", bad ? "opened" : "NULL", vdg_last_error());
    vdg_close(bad);
    free(bytes);

    /* Each call before reading its message: C leaves the order in which
     * printf's arguments are evaluated open. */
    fl = vdg_clearance(NULL, p);
    printf("E clearance-null-graph %s %s\n", isnan(fl) ? "NaN" : "number", vdg_last_error());
    fl = vdg_clearance(g, nan3);
    printf("E clearance-nan %s %s\n", isnan(fl) ? "NaN" : "number", vdg_last_error());
    rc = vdg_visible(g, p, NULL);
    printf("E visible-null-point %d %s\n", rc, vdg_last_error());
    n = vdg_path(g, p, p, -1.0f, NULL, 0, NULL);
    printf("E path-negative-radius %ld %s\n", (long)n, vdg_last_error());
    n = vdg_path(g, p, p, 0.0f, NULL, 4, NULL);
    printf("E path-null-buffer %ld %s\n", (long)n, vdg_last_error());
    printf("E path-size-only %ld\n", (long)vdg_path(g, p, p, 0.0f, NULL, 0, NULL));
    cam = vdg_camera_new(g, "distance_mu = \"far\"");
    printf("E camera-bad-params %s %s\n", cam ? "made" : "NULL", vdg_last_error());
    vdg_camera_free(cam);
    cam = vdg_camera_new(g, NULL);
    rc = vdg_camera_update(cam, g, &targets[0], NAN, &pose);
    printf("E camera-nan-dt %d %s\n", rc, vdg_last_error());
    rc = vdg_camera_update(cam, g, &targets[0], 0.0f, NULL);
    printf("E camera-null-out %d %s\n", rc, vdg_last_error());
    vdg_camera_free(cam);
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The camera frames REPEAT times with a fresh camera each time; prints the
 * median over repetitions of the mean time per frame. */
static void bench(const vdg_graph *g, int repeat) {
    double *t = malloc(sizeof(double) * (size_t)repeat);
    vdg_pose pose;
    if (!t)
        exit(2);
    for (int r = 0; r < repeat; r++) {
        vdg_camera *cam = vdg_camera_new(g, NULL);
        double t0 = now();
        vdg_camera_reset(cam, g, &targets[0], &pose);
        for (int i = 1; i < n_frames; i++)
            vdg_camera_update(cam, g, &targets[i], dts[i], &pose);
        t[r] = (now() - t0) / n_frames;
        vdg_camera_free(cam);
    }
    qsort(t, (size_t)repeat, sizeof *t, cmp_double);
    fprintf(stderr, "C camera: median %.2f us/frame over %d runs of %d frames\n",
            t[repeat / 2] * 1e6, repeat, n_frames);
    free(t);
}

int main(int argc, char **argv) {
    vdg_graph *from_path, *from_memory;
    unsigned char *bytes;
    size_t len;
    int repeat = argc > 4 ? atoi(argv[4]) : 0;
    if (argc < 4) {
        fprintf(stderr, "usage: smoke GRAPH.vdg SCRIPT CORRUPT.vdg [REPEAT]\n");
        return 2;
    }
    read_script(argv[2]);
    if (n_frames == 0) {
        fprintf(stderr, "smoke: no frames in %s\n", argv[2]);
        return 2;
    }
    from_path = vdg_open(argv[1]);
    if (!from_path)
        die("vdg_open");
    bytes = read_file(argv[1], &len);
    from_memory = vdg_open_memory(bytes, len);
    /* The image was copied: the caller's buffer may go at once. */
    memset(bytes, 0xAB, len);
    free(bytes);
    if (!from_memory)
        die("vdg_open_memory");

    run_queries("P", from_path);
    run_queries("M", from_memory);
    run_camera(from_path, from_memory);
    run_director(from_path);
    run_errors(from_path, argv[3]);
    if (repeat > 0)
        bench(from_path, repeat);

    vdg_close(from_memory);
    vdg_close(from_path);
    return 0;
}
