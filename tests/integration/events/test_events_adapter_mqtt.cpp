// The adapter-level event tests about the wire (tests/unit/events/
// test_events_adapter.cpp) again, through a real mosquitto: both response
// spellings, response-before-event order, every filter type and variance,
// every Register/Event error code, malformed requests, Event/{dev} without a
// terminal id. Triggers, elements, 416, release on offline and lease expiry
// run on the simulated machine in test_events_sim_mqtt.cpp.
#define NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO 1
#include "../../unit/events/test_events_adapter.cpp"
