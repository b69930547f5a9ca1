#include "machine.h"

#include <math.h>
#include <string.h>

void machine_init(machine* m) {
    memset(m, 0, sizeof *m);
    pthread_mutex_init(&m->lock, NULL);
    m->feed_override = 100;
    m->now.status = "free";
    m->published = m->now;
}

void machine_destroy(machine* m) { pthread_mutex_destroy(&m->lock); }

void machine_servo_step(machine* m, double dt) {
    int feed = 100, homing = 0;
    /* The cycle: 4 s running, 1 s free; a part done at the end of each run. */
    const double phase = fmod(m->time_s, 5.0);
    if (pthread_mutex_trylock(&m->lock) == 0) {
        feed = m->feed_override;
        homing = m->homing;
        pthread_mutex_unlock(&m->lock);
    }
    if (!homing) m->time_s += dt * feed / 100.0;
    {
        const double t = m->time_s;
        const int running = !homing && phase < 4.0;
        if (m->now.status != NULL && strcmp(m->now.status, "running") == 0 && !running && !homing) ++m->now.part_count;
        m->now.status = homing ? "holding" : running ? "running" : "free";
        if (running) {
            m->now.position[0] = 100.0 * sin(t);
            m->now.position[1] = 50.0 * cos(t);
            m->now.position[2] = -10.0 + 2.0 * sin(3.0 * t);
            m->now.spindle_speed = 2400.0 * feed / 100.0;
        } else {
            m->now.spindle_speed = 0.0;
        }
    }
    if (pthread_mutex_trylock(&m->lock) == 0) {
        int axis;
        if (m->homing) /* the method moved the axes: keep its positions */
            for (axis = 0; axis < MACHINE_AXES; ++axis) m->now.position[axis] = m->published.position[axis];
        m->published = m->now;
        pthread_mutex_unlock(&m->lock);
    }
}

machine_snapshot machine_read(machine* m) {
    machine_snapshot s;
    pthread_mutex_lock(&m->lock);
    s = m->published;
    pthread_mutex_unlock(&m->lock);
    return s;
}

void machine_home_axis(machine* m, int axis) {
    if (axis < 0 || axis >= MACHINE_AXES) return;
    pthread_mutex_lock(&m->lock);
    m->published.position[axis] = 0.0;
    pthread_mutex_unlock(&m->lock);
}

int machine_feed_override(machine* m) {
    int percent;
    pthread_mutex_lock(&m->lock);
    percent = m->feed_override;
    pthread_mutex_unlock(&m->lock);
    return percent;
}

void machine_set_feed_override(machine* m, int percent) {
    pthread_mutex_lock(&m->lock);
    m->feed_override = percent;
    pthread_mutex_unlock(&m->lock);
}

void machine_set_homing(machine* m, int homing) {
    pthread_mutex_lock(&m->lock);
    m->homing = homing;
    pthread_mutex_unlock(&m->lock);
}
