// The adapter's request tests (tests/unit/adapter/test_adapter_requests.cpp)
// again, through a real mosquitto: Query and Set of every data type and
// operation, every error code they reach, mirror topics with and without ex,
// retained and repeated requests, malformed JSON and wrong keys.
#define NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO 1
#include "../../unit/adapter/test_adapter_requests.cpp"
