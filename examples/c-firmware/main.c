/* nclink-c-firmware: controller firmware written in C that embeds an NC-Link
 * adapter (nclink/nclink.h). A fake 3-axis mill (machine.c) answers reads,
 * a Set of feed_override and the method home_axes through its driver
 * (driver.c); its servo loop, a real-time thread of its own, pushes a row of
 * positions into the sample channel ch_servo every 10 ms; the main loop
 * tells the adapter when the run status changes (events).
 *
 *   nclink-c-firmware [--broker URL] [--model FILE] [--seconds N]
 *
 * Runs until SIGINT/SIGTERM, or N seconds (0: start, push, stop at once).
 * docs/porting-guide.md, "From C firmware", explains each step. */
#define _POSIX_C_SOURCE 200809L

#include "driver.h"
#include "machine.h"

#include <nclink/driver_plugin_helpers.h>
#include <nclink/nclink.h>

#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifndef C_FIRMWARE_MODEL
#define C_FIRMWARE_MODEL "model.json"
#endif

#define SERVO_PERIOD_NS 10000000L /* 10 ms: the channel's sampleInterval */

static volatile sig_atomic_t stop_requested = 0;
static void on_signal(int signal_number) {
    (void)signal_number;
    stop_requested = 1;
}

typedef struct servo {
    machine* m;
    nclink_channel* channel;
    volatile int run;
    unsigned long pushed, refused;
} servo;

/* The real-time thread: a fixed-period loop on CLOCK_MONOTONIC. Each cycle
 * moves the machine and pushes one row; nclink_channel_push() is wait-free,
 * so the loop never waits for nclink. */
static void* servo_loop(void* arg) {
    servo* s = (servo*)arg;
    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    while (s->run) {
        nclink_value row[4];
        int axis;
        machine_servo_step(s->m, SERVO_PERIOD_NS / 1e9);
        for (axis = 0; axis < MACHINE_AXES; ++axis) {
            row[axis].kind = NCLINK_VALUE_FLOAT64;
            row[axis].as.float64 = s->m->now.position[axis];
        }
        row[3].kind = NCLINK_VALUE_FLOAT64;
        row[3].as.float64 = s->m->now.spindle_speed;
        if (nclink_channel_push(s->channel, row, 4, 0) == NCLINK_OK) ++s->pushed;
        else ++s->refused;
        next.tv_nsec += SERVO_PERIOD_NS;
        if (next.tv_nsec >= 1000000000L) {
            next.tv_nsec -= 1000000000L;
            ++next.tv_sec;
        }
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
    }
    return NULL;
}

/* nclink's log lines on stderr (called from any SDK thread). */
static void log_line(void* context, int level, const char* message) {
    static const char* const names[] = {"trace", "debug", "info", "warn", "error"};
    (void)context;
    fprintf(stderr, "nclink %s: %s\n", names[level < 0 ? 0 : level > 4 ? 4 : level], message);
}

int main(int argc, char** argv) {
    const char* broker = "tcp://127.0.0.1:1883";
    const char* model = C_FIRMWARE_MODEL;
    long seconds = -1;
    char config[512];
    nclink_json_writer w;
    nclink_error err = NCLINK_ERROR_INIT;
    nclink_adapter_options options = NCLINK_ADAPTER_OPTIONS_INIT;
    nclink_adapter* adapter = NULL;
    machine m;
    servo s;
    pthread_t servo_thread;
    const char* last_status = NULL;
    long ticks = 0;
    int i, code = 0;

    for (i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--broker") == 0 && i + 1 < argc) broker = argv[++i];
        else if (strcmp(argv[i], "--model") == 0 && i + 1 < argc) model = argv[++i];
        else if (strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) seconds = strtol(argv[++i], NULL, 10);
        else {
            fprintf(stderr, "usage: %s [--broker URL] [--model FILE] [--seconds N]\n", argv[0]);
            return 2;
        }
    }

    /* The configuration (docs/configuration.md) as JSON text: the broker and
     * the push-mode channel. The helpers escape the URL. */
    nclink_json_init(&w, config, sizeof config);
    nclink_json_begin_object(&w);
    nclink_json_key(&w, "broker");
    nclink_json_begin_object(&w);
    nclink_json_key(&w, "url");
    nclink_json_string(&w, broker);
    nclink_json_end_object(&w);
    nclink_json_key(&w, "sampling");
    nclink_json_begin_object(&w);
    nclink_json_key(&w, "push_channels");
    nclink_json_begin_array(&w);
    nclink_json_string(&w, "ch_servo");
    nclink_json_end_array(&w);
    nclink_json_end_object(&w);
    /* One request worker, even in a burst of requests: Query and Set run on
     * the driver's worker, so the adapter stays at six threads. (The default,
     * 2, also runs six at rest and starts the second worker only while
     * requests queue up; docs/footprint.md.) */
    nclink_json_key(&w, "request_threads");
    nclink_json_int(&w, 1);
    nclink_json_key(&w, "log_level");
    nclink_json_string(&w, "warn");
    nclink_json_end_object(&w);
    if (!nclink_json_ok(&w)) {
        fprintf(stderr, "c-firmware: broker URL too long\n");
        return 2;
    }

    machine_init(&m);
    firmware_machine = &m;
    options.config_json = config;
    options.model_path = model;
    options.driver = firmware_driver();
    options.log = log_line;
    if (nclink_adapter_create(&options, &adapter, &err) != NCLINK_OK || nclink_adapter_start(adapter, &err) != NCLINK_OK) {
        fprintf(stderr, "c-firmware: %d %s: %s\n", err.code, nclink_error_message(err.code), err.message);
        nclink_adapter_destroy(adapter);
        machine_destroy(&m);
        return 1;
    }
    memset(&s, 0, sizeof s);
    s.m = &m;
    s.run = 1;
    if (nclink_adapter_push_channel(adapter, "ch_servo", &s.channel, &err) != NCLINK_OK) {
        fprintf(stderr, "c-firmware: ch_servo: %d %s\n", err.code, err.message);
        code = 1;
        goto out;
    }
    if (pthread_create(&servo_thread, NULL, servo_loop, &s) != 0) {
        fprintf(stderr, "c-firmware: cannot start the servo thread\n");
        code = 1;
        goto out;
    }
    printf("c-firmware: serving %s on %s\n", model, broker);
    fflush(stdout);

    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    /* The main loop: every 100 ms, tell the adapter when the status changed
     * (events fire at once instead of at their next poll). */
    while (!stop_requested && (seconds < 0 || ticks < seconds * 10)) {
        const struct timespec tick = {0, 100 * 1000 * 1000};
        const machine_snapshot now = machine_read(&m);
        if (last_status == NULL || strcmp(last_status, now.status) != 0) {
            nclink_value v;
            v.kind = NCLINK_VALUE_TEXT;
            v.as.text = now.status;
            v.length = (uint32_t)strlen(now.status);
            (void)nclink_adapter_notify(adapter, "status", &v);
            last_status = now.status;
        }
        nanosleep(&tick, NULL);
        ++ticks;
    }
    s.run = 0;
    pthread_join(servo_thread, NULL);
    printf("c-firmware: %lu rows pushed, %lu refused\n", s.pushed, s.refused);

out:
    nclink_adapter_stop(adapter, 2000);
    nclink_channel_release(s.channel);
    nclink_adapter_destroy(adapter);
    machine_destroy(&m);
    return code;
}
