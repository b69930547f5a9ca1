/* The C firmware's driver: the machine's points as an nclink driver
 * descriptor (nclink/driver_plugin.h), handed to nclink_adapter_create(). */
#ifndef C_FIRMWARE_DRIVER_H
#define C_FIRMWARE_DRIVER_H

#include "machine.h"

#include <nclink/driver_plugin.h>

/* The descriptor. Its create() takes the machine from `firmware_machine`,
 * which main() sets before nclink_adapter_create(). */
const nclink_driver_descriptor* firmware_driver(void);
extern machine* firmware_machine;

#endif
