/* The fake machine of the C firmware example: three linear axes and a
 * spindle moved by a "servo loop", a run status that cycles, a part counter
 * and a settable feed override. The servo loop owns the motion; everybody
 * else reads a snapshot it publishes without ever blocking (trylock). */
#ifndef C_FIRMWARE_MACHINE_H
#define C_FIRMWARE_MACHINE_H

#include <pthread.h>

#define MACHINE_AXES 3

typedef struct machine_snapshot {
    double position[MACHINE_AXES]; /* mm */
    double spindle_speed;          /* r/min */
    const char* status;            /* "running", "free" or "holding" (STATUS, table 15) */
    long part_count;
} machine_snapshot;

typedef struct machine {
    pthread_mutex_t lock; /* guards `published`, `feed_override` and `homing` */
    machine_snapshot published;
    int feed_override; /* percent, 0..150 */
    int homing;        /* nonzero while home_axes runs: the servo loop holds the axes */
    /* Servo-loop state: only the servo thread touches these. */
    double time_s;
    machine_snapshot now;
} machine;

void machine_init(machine* m);
void machine_destroy(machine* m);
/* One servo cycle of dt seconds: moves the axes and fills `now`; publishes
 * it when the lock is free (never waits: this runs in the real-time loop). */
void machine_servo_step(machine* m, double dt);
/* A consistent copy of the last published snapshot (takes the lock). */
machine_snapshot machine_read(machine* m);
int machine_feed_override(machine* m);
void machine_set_feed_override(machine* m, int percent);
/* While set, the servo loop holds the axes where the method puts them. */
void machine_set_homing(machine* m, int homing);
/* Moves one axis to its reference point (0 mm): the home_axes method. */
void machine_home_axis(machine* m, int axis);

#endif
