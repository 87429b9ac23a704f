/* A reference client of usvtool's process controller, protocol 1 (docs/protocol.md), in C with
 * libc and libm only.
 *
 *     cc -O2 -o examples/exec/build/client examples/exec/client.c -lm
 *     usvtool simulate charts/scenarios/env1-head-on.yaml \
 *         --controller exec:examples/exec/build/client -o trace.csv
 *
 * The rule ("starboard on a close CPA") is examples/exec/client.py's:
 *
 * - the aim is the goal, or with a route the first of its points not yet within `reach` (the
 *   goal tolerance, at least two ship lengths) of the own ship, taken in order;
 * - a target is a threat to a course when its relative bearing is within 112.5 degrees of the
 *   bow (not one overtaking her), and, were she to sail that course at her top speed, its
 *   closest point of approach would be ahead in time (0 < tcpa <= HORIZON s) and closer than
 *   2 (L_own + L_target);
 * - the course is the first of the bearing to the aim, then that bearing less STEP, 2 STEP,
 *   ... TURNS STEP (turns to starboard: angles are counter-clockwise from east), that no
 *   target is a threat to; the last when every one has a threat; the speed is her top speed.
 *
 * By default it tracks the course itself and replies with a velocity pair within the vessel's
 * limits (the shaped proportional controller of usvtool's autopilot); with --course it replies
 * with the course-and-speed reference instead, and with --trivial with the present speed and
 * yaw rate (no decision: the protocol's overhead, benchmarks/bench_protocol.py).
 *
 * The JSON reader is a small one for the messages of protocol 1: it finds a top-level key by
 * its quoted name followed by a colon (usvtool writes no such text inside a string value) and
 * reads numbers with strtod, which reads usvtool's shortest round-trip decimals exactly; the
 * replies are written with %.17g, which strtod (and Python's float) read back exactly.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HORIZON 120.0 /* s */
#define STEP (15.0 * M_PI / 180.0)
#define TURNS 6
#define GAIN 0.5      /* 1/s */
#define MAX_TARGETS 1024
#define MAX_ROUTE 65536

enum mode { VELOCITY, COURSE, TRIVIAL };

struct vessel {
    double length, min_speed, max_speed, max_accel, max_decel, max_yaw_rate, max_yaw_accel;
};

static struct vessel ship;
static double dt, reach;
static double route[MAX_ROUTE][2];
static int route_points, next_point;
static double targets[MAX_TARGETS][5];

static void fail(const char *why) {
    fprintf(stderr, "client.c: %s\n", why);
    exit(2);
}

/* The text after "key": in line, or NULL. */
static const char *field(const char *line, const char *key) {
    char quoted[64];
    snprintf(quoted, sizeof quoted, "\"%s\":", key);
    const char *at = strstr(line, quoted);
    return at ? at + strlen(quoted) : NULL;
}

static double number(const char *line, const char *key) {
    const char *at = field(line, key);
    char *end;
    if (!at) fail("a field is missing");
    double value = strtod(at, &end);
    if (end == at) fail("a field is not a number");
    return value;
}

/* Reads up to max numbers of a flat or nested array of numbers at p into out; returns how
 * many, and leaves *p after the array's closing bracket. */
static int numbers(const char **p, double *out, int max) {
    int depth = 0, n = 0;
    const char *s = *p;
    do {
        if (*s == '[') depth++, s++;
        else if (*s == ']') depth--, s++;
        else if (*s == ',' || *s == ' ') s++;
        else if (*s == '\0') fail("an array is cut short");
        else {
            char *end;
            double value = strtod(s, &end);
            if (end == s) fail("an array holds something other than numbers");
            if (n < max) out[n] = value;
            n++;
            s = end;
        }
    } while (depth > 0);
    *p = s;
    return n;
}

static double wrap(double a) { return remainder(a, 2 * M_PI); }
static double clamp(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

/* The yaw rate that turns onto course (usvtool's autopilot: docs/protocol.md). */
static double track(const double *own, double course) {
    double error = wrap(course - own[2]), accel = ship.max_yaw_accel;
    double linear = accel / (GAIN * GAIN), rate;
    if (fabs(error) <= linear) rate = GAIN * error;
    else rate = copysign(sqrt(2 * accel * (fabs(error) - linear / 2)), error);
    rate = clamp(rate, -fabs(error) / dt, fabs(error) / dt);
    rate = clamp(rate, own[4] - accel * dt, own[4] + accel * dt);
    return clamp(rate, -ship.max_yaw_rate, ship.max_yaw_rate);
}

/* Whether target t is a threat to the own ship sailing course at speed (the rule above). */
static int threat(const double *own, const double *t, double course, double speed) {
    double px = t[0] - own[0], py = t[1] - own[1];
    if (fabs(wrap(atan2(py, px) - own[2])) > 112.5 * M_PI / 180.0) return 0;
    double wx = t[2] - speed * cos(course), wy = t[3] - speed * sin(course);
    double w2 = wx * wx + wy * wy;
    if (w2 < 1e-12) return 0;
    double tcpa = -(px * wx + py * wy) / w2;
    double dcpa = hypot(px + tcpa * wx, py + tcpa * wy);
    return 0 < tcpa && tcpa <= HORIZON && dcpa < 2 * (ship.length + t[4]);
}

static double decide(const double *own, int k) {
    while (next_point < route_points - 1
           && hypot(route[next_point][0] - own[0], route[next_point][1] - own[1]) <= reach)
        next_point++;
    double aim = atan2(route[next_point][1] - own[1], route[next_point][0] - own[0]);
    double course = aim;
    for (int turn = 0; turn <= TURNS; turn++) {
        course = aim - turn * STEP;
        int any = 0;
        for (int i = 0; i < k && !any; i++) any = threat(own, targets[i], course, ship.max_speed);
        if (!any) break;
    }
    return course;
}

int main(int argc, char **argv) {
    enum mode mode = VELOCITY;
    if (argc > 1 && strcmp(argv[1], "--course") == 0) mode = COURSE;
    else if (argc > 1 && strcmp(argv[1], "--trivial") == 0) mode = TRIVIAL;
    else if (argc > 1 && strcmp(argv[1], "--velocity") != 0) fail("options: --velocity, --course or --trivial");

    char *line = NULL;
    size_t size = 0;
    if (getline(&line, &size, stdin) < 0) fail("no hello");
    if (number(line, "protocol") != 1) fail("the hello's protocol is not 1");
    dt = number(line, "dt");
    ship.length = number(line, "length");
    ship.min_speed = number(line, "min_speed");
    ship.max_speed = number(line, "max_speed");
    ship.max_accel = number(line, "max_accel");
    ship.max_decel = number(line, "max_decel");
    ship.max_yaw_rate = number(line, "max_yaw_rate");
    ship.max_yaw_accel = number(line, "max_yaw_accel");
    double tolerance = number(line, "goal_tolerance");
    reach = tolerance > 2 * ship.length ? tolerance : 2 * ship.length;
    const char *p = field(line, "route");
    if (p && *p == '[') {
        route_points = numbers(&p, &route[0][0], 2 * MAX_ROUTE) / 2;
        if (route_points > MAX_ROUTE) fail("the route has too many points");
    } else {
        p = field(line, "goal");
        if (!p || numbers(&p, route[0], 2) != 2) fail("no goal");
        route_points = 1;
    }
    fprintf(stderr, "client.c: protocol 1, seed %.0f, %s replies, %d route points\n",
            number(line, "seed"), mode == COURSE ? "course" : mode == TRIVIAL ? "trivial" : "velocity",
            route_points);
    fputs("{\"protocol\":1}\n", stdout);
    fflush(stdout);

    long steps = 0;
    while (getline(&line, &size, stdin) >= 0) {
        double own[5];
        p = field(line, "own");
        if (!p || numbers(&p, own, 5) != 5) fail("a step without its own ship");
        p = field(line, "targets");
        if (!p) fail("a step without its targets");
        int k = numbers(&p, &targets[0][0], 5 * MAX_TARGETS) / 5;
        if (k > MAX_TARGETS) fail("too many targets");
        if (mode == TRIVIAL) {
            printf("{\"v\":%.17g,\"omega\":%.17g}\n", own[3], own[4]);
        } else {
            double course = decide(own, k);
            if (mode == COURSE) {
                printf("{\"course\":%.17g,\"speed\":%.17g}\n", course, ship.max_speed);
            } else {
                double v = clamp(ship.max_speed, own[3] - ship.max_decel * dt,
                                 own[3] + ship.max_accel * dt);
                printf("{\"v\":%.17g,\"omega\":%.17g}\n", v, track(own, course));
            }
        }
        fflush(stdout);
        steps++;
    }
    fprintf(stderr, "client.c: end of input after %ld steps\n", steps);
    free(line);
    return 0;
}
