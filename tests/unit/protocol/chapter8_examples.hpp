// Every example DTU printed in GB/T 41970-2022 chapter 8, with the standard's
// typos fixed (each fix noted next to its example). The fuzz seed corpus
// tests/fuzz/corpus/dtu/ holds the same texts, one file each (checked by a test).
#pragma once

#include <string_view>

namespace chapter8 {

/// Which decoder an example goes through.
enum class Dtu {
    register_request,
    register_response,
    discovery_request,
    discovery_response,
    probe_version_request,
    probe_version_response,
    probe_query_request,
    probe_query_response,
    probe_set_request,
    probe_set_response,
    query_request,
    query_response,
    set_request,
    set_response,
    sample,
    notify_state,
    sample_register_request,
    sample_register_response,
    sample_unregister_request,
    sample_unregister_response,
    method_call,
    method_status,
    method_result,
    method_control_request,
    method_control_response,
    event_register_request,
    event_register_response,
    event_unregister_request,
    event_unregister_response,
    event_data,
    dev_unreachable,
};

struct Example {
    std::string_view name;  ///< also the corpus file name (+ ".json")
    Dtu dtu;
    std::string_view json;
    bool complete;  ///< nclink's encoding equals the example's JSON value
};

// clang-format off
inline constexpr Example kExamples[] = {
    // 8.2.1 example 1. Fixed: closing brace missing; trailing space in "dev_uuid ".
    {"8.2.1_ex1_register_request", Dtu::register_request, R"({
  "@id": "some_mid_001",
  "cli_uuid": "dev_uuid"
})", true},
    // 8.2.1 example 2. Fixed: trailing space in "ex_cid ".
    {"8.2.1_ex2_register_request", Dtu::register_request, R"({
  "@id": "some_mid_001",
  "cli_uuid": "ex_cid"
})", true},
    // 8.2.2 example 1 (as printed).
    {"8.2.2_ex1_register_response", Dtu::register_response, R"({
  "@id": "some_mid_001",
  "cli_uuid": "dev_uuid",
  "code": "NG",
  "reason": "Permission Denied",
  "error": 301
})", true},
    // 8.2.2 example 2. Fixed: missing comma after "code": "NG".
    {"8.2.2_ex2_register_response", Dtu::register_response, R"({
  "@id": "some_mid_001",
  "cli_uuid": "ex_cid",
  "code": "NG",
  "reason": "Permission Denied"
})", true},
    // 8.2.3 (as printed).
    {"8.2.3_discovery_request", Dtu::discovery_request, R"({
  "@id": "some_mid_001",
  "guid": "ex_cid"
})", true},
    // 8.2.4 (as printed).
    {"8.2.4_discovery_response", Dtu::discovery_response, R"({
  "@id": "some_mid_001",
  "code": "OK",
  "guid": "ex_cid",
  "deviceList": [
    {"guid": "dev_uuid_1", "status": "online", "lastAliveTimeStamp": "1611287021", "privateInfo": null},
    {"guid": "dev_uuid_2", "status": "offline", "lastAliveTimeStamp": "1611176010", "privateInfo": null},
    {"guid": "dev_uuid_3", "status": "online", "lastAliveTimeStamp": "1611287160"}
  ]
})", true},
    // 8.2.5 (as printed).
    {"8.2.5_probe_version_request", Dtu::probe_version_request, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "version": "v1.0.1",
  "privateInfo": null
})", true},
    // 8.2.6 (as printed).
    {"8.2.6_probe_version_response", Dtu::probe_version_response, R"({
  "@id": "some_mid_001",
  "code": "OK",
  "guid": "dev_uuid",
  "version": "v1.0.1",
  "privateInfo": null
})", true},
    // 8.2.7 (as printed).
    {"8.2.7_probe_query_request", Dtu::probe_query_request, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "privateInfo": null
})", true},
    // 8.2.8. Fixed: the placeholder "probe": "{……}" is a (small) model object.
    {"8.2.8_probe_query_response", Dtu::probe_query_response, R"({
  "@id": "some_mid_001",
  "code": "OK",
  "probe": {"id": "machine", "guid": "dev_uuid", "version": "1.0.0", "devices": []}
})", true},
    // 8.2.9. Fixed: the placeholder "probe": "{……}" is a model object.
    {"8.2.9_probe_set_request", Dtu::probe_set_request, R"({
  "@id": "some_mid_001",
  "probe": {"id": "machine", "guid": "dev_uuid", "version": "1.0.1", "devices": []}
})", true},
    // 8.2.10 (as printed).
    {"8.2.10_probe_set_response", Dtu::probe_set_response, R"({
  "@id": "some_mid_001",
  "code": "OK"
})", true},
    // 8.2.11 examples 1-3b (as printed; a stray "}" after example 3b is outside the DTU).
    {"8.2.11_ex1_query_request", Dtu::query_request, R"({
  "@id" : "some_mid_x1",
  "guid" : "dev_uuid",
  "ids" : [{"id" : "010203"}, {"id" : "010204"}]
})", true},
    {"8.2.11_ex2a_query_request", Dtu::query_request, R"({
  "@id" : "some_mid_x2",
  "guid" : "dev_uuid",
  "ids" : [ {"id" : "011213", "params" : {"operation" : "get_keys"}} ]
})", true},
    {"8.2.11_ex2b_query_request", Dtu::query_request, R"({
  "@id" : "some_mid_x3",
  "guid" : "dev_uuid",
  "ids" : [ {"id" : "011213", "params" : {"operation" : "get_attributes", "keys":["k1", "k2"]} } ]
})", true},
    {"8.2.11_ex2c_query_request", Dtu::query_request, R"({
  "@id" : "some_mid_x4",
  "guid" : "dev_uuid",
  "ids" : [ {"id" : "011213", "params" : {"operation": "get_value", "keys":["k1", "k2"]} } ]
})", true},
    {"8.2.11_ex3a_query_request", Dtu::query_request, R"({
  "@id" : "some_mid_x5",
  "guid" : "dev_uuid",
  "ids" : [ {"id" : "012223", "params" : {"operation": "get_length"}} ]
})", true},
    {"8.2.11_ex3b_query_request", Dtu::query_request, R"({
  "@id" : "some_mid_x6",
  "guid" : "dev_uuid",
  "ids" : [ {"id" : "012223", "params": {"operation": "get_value", "indexes":["0", "5-8"]} } ]
})", true},
    // 8.2.12 example 1. Fixed: reason " Unavailable" had a leading space, and
    // its error 301 (Permission Denied) contradicted it: Unavailable is 202.
    {"8.2.12_ex1_query_response", Dtu::query_response, R"({
  "@id" : "some_mid_x1",
  "guid" : "dev_uuid",
  "values" : [
    { "id" : "010203", "values" : [2, "str1", [1, 2, 3], 100.23], "code" : "OK" },
    { "id" : "010204", "code" : "NG", "reason" : "Unavailable", "error" : 202 }
  ]
})", true},
    // 8.2.12 examples 2a-3b (as printed).
    {"8.2.12_ex2a_query_response", Dtu::query_response, R"({
  "@id" : "some_mid_x2",
  "guid" : "dev_uuid",
  "values" : [
    { "id" : "011213", "code" : "OK", "params" : { "operation" : "get_keys" }, "values" : [ "k1", "k2", "k3" ] }
  ]
})", true},
    {"8.2.12_ex2b_query_response", Dtu::query_response, R"({
  "@id" : "some_mid_x3",
  "guid" : "dev_uuid",
  "values" : [
    { "id" : "011213", "code" : "OK", "params" : { "operation" : "get_attributes", "keys": ["k1", "k2"] },
      "values" : [ "key_attr_1", "key_attr_2" ] }
  ]
})", true},
    {"8.2.12_ex2c_query_response", Dtu::query_response, R"({
  "@id" : "some_mid_x4",
  "guid" : "dev_uuid",
  "values" : [
    { "id" : "011213", "code" : "OK", "params" : {"operation" : "get_value", "keys":["k1", "k2", "k3"]},
      "values" : [1234, "kv_string", [1, 2, 3, 4]] }
  ]
})", true},
    {"8.2.12_ex3a_query_response", Dtu::query_response, R"({
  "@id" : "some_mid_x5",
  "guid" : "dev_uuid",
  "values" : [ { "id" : "012223", "code" : "OK", "params" : {"operation" : "get_length"}, "values" : [10] } ]
})", true},
    {"8.2.12_ex3b_query_response", Dtu::query_response, R"({
  "@id" : "some_mid_x6",
  "guid" : "dev_uuid",
  "values" : [
    { "id" : "012223", "code" : "OK", "params" : {"operation" : "get_value", "indexes" : ["0", "4-7"]},
      "values" : [100.234, 50, "str_v_6", [1.1, 2.2, 3.3], 8] }
  ]
})", true},
    // 8.2.13 examples 1 and 2a (as printed).
    {"8.2.13_ex1_set_request", Dtu::set_request, R"({
  "@id" : "some_mid_x1",
  "guid" : "dev_uuid",
  "values" : [
    {"id": "000006", "params": {"value": 12.5}},
    {"id": "000008", "params": {"operation": "set_value", "value": 22.3}}
  ]
})", true},
    {"8.2.13_ex2a_set_request", Dtu::set_request, R"({
  "@id" : "some_mid_x2",
  "guid" : "dev_uuid",
  "values" : [
    {"id": "011213", "params": {"operation": "set_value", "key": "k1", "value": 2}},
    {"id": "000003", "params": {"key": "k1", "value": 2}}
  ]
})", true},
    // 8.2.13 example 2b. Fixed: trailing comma after the only entry.
    {"8.2.13_ex2b_set_request", Dtu::set_request, R"({
  "@id" : "some_mid_x3",
  "guid" : "dev_uuid",
  "values" : [
    {"id": "011213", "params": {"operation": "add", "key": "AAA", "value": "111"}}
  ]
})", true},
    // 8.2.13 example 2c. Fixed: trailing comma after the only entry (and a stray "}" after the DTU).
    {"8.2.13_ex2c_set_request", Dtu::set_request, R"({
  "@id" : "some_mid_x4",
  "guid" : "dev_uuid",
  "values" : [
    {"id": "011213", "params": {"operation": "delete", "key": "AAA"}}
  ]
})", true},
    // 8.2.13 example 3 (as printed).
    {"8.2.13_ex3_set_request", Dtu::set_request, R"({
  "@id" : "some_mid_x5",
  "guid" : "dev_uuid",
  "values" : [
    { "id" : "012223", "params" : { "operation" : "set_value", "index" : 0, "offset" : 5, "length" : 10, "value" : 16 } }
  ]
})", true},
    // 8.2.14 examples 1 and 2 (as printed).
    {"8.2.14_ex1_set_response", Dtu::set_response, R"({
  "@id" : "some_mid_x1",
  "guid" : "dev_uuid",
  "results" : [
    { "id": "000006", "code": "OK" },
    { "id": "000008", "code": "NG", "reason": "Permission Denied", "error": 301,
      "params" : { "operation": "set_value" } }
  ]
})", true},
    {"8.2.14_ex2_set_response", Dtu::set_response, R"({
  "@id" : "some_mid_x2",
  "guid" : "dev_uuid",
  "results" : [
    { "id" : "011213", "code" : "OK", "params" : { "operation" : "set_values", "key": ["k1", "k2"] } }
  ]
})", true},
    // 8.2.14 example 3. Fixed: the list is "results" (table 35), not "values".
    {"8.2.14_ex3_set_response", Dtu::set_response, R"({
  "@id" : "some_mid_x5",
  "guid" : "dev_uuid",
  "results" : [
    { "id" : "012223", "code": "OK",
      "params": { "operation": "set_value", "index": ["0"], "offset": 5, "length": 10 } }
  ]
})", true},
    // 8.2.15. Fixed: trailing comma after the last data entry.
    {"8.2.15_sample", Dtu::sample, R"({
  "id": "cn1",
  "guid": "dev_uuid",
  "beginTime": "1535642875900",
  "data": [
    {"data": [414.262, 414.262, 414.262]},
    {"data": [414.262, 414.262, 414.262]},
    {"data": [0, 0, 0]},
    {"data": [0, 0, 0]}
  ]
})", true},
    // 8.2.16 (as printed).
    {"8.2.16_notify_state", Dtu::notify_state, R"({
  "tid": "dev_001",
  "state": "offline"
})", true},
    // 8.2.17. Fixed: missing comma after "guid"; trailing space in "dev_uuid ".
    {"8.2.17_sample_register_request", Dtu::sample_register_request, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "sampleInterval": 20000,
  "uploadInterval": 20000,
  "ids": [ {"id": "010302"}, {"id": "010305"}, {"id": "010306"}, {"id": "010307"} ]
})", true},
    // 8.2.18 (as printed).
    {"8.2.18_sample_register_response", Dtu::sample_register_response, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "channel_01",
  "code": "OK"
})", true},
    // 8.2.19. Fixed: trailing space in "dev_uuid ".
    {"8.2.19_sample_unregister_request", Dtu::sample_unregister_request, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "channel_01"
})", true},
    // 8.2.20 (as printed).
    {"8.2.20_sample_unregister_response", Dtu::sample_unregister_response, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "code": "OK"
})", true},
    // 8.2.21. Fixed: trailing comma after the last data entry. (No guid, as printed: liberal.)
    {"8.2.21_dynamic_sample", Dtu::sample, R"({
  "id": "cn1",
  "beginTime": "1535642875900",
  "data": [
    {"data": [414.262, 414.262, 414.262]},
    {"data": [414.262, 414.262, 414.262]},
    {"data": [0, 0, 0]},
    {"data": [0, 0, 0]}
  ]
})", true},
    // 8.2.22 (as printed).
    {"8.2.22_method_call", Dtu::method_call, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "method_01",
  "args": {
    "protocol": "FTP", "address": "10.10.56.1:21", "user": "user1", "password": "111111",
    "source": "/gcodes/O1", "destination": "/h/lnc8/prog/O1", "operation": "push"
  }
})", true},
    // 8.2.23. Fixed: "process" is "progress" (table 44); trailing space in "method_01 ".
    {"8.2.23_method_status", Dtu::method_status, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "method_01",
  "status": "executing",
  "progress": 30
})", true},
    // 8.2.24 (as printed).
    {"8.2.24_method_result", Dtu::method_result, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "method_01",
  "result": "finished",
  "code": "OK",
  "return": [ {"name": "O1", "size": "100"}, {"name": "AC", "directory": "true"} ]
})", true},
    // 8.2.25 (as printed).
    {"8.2.25_method_control_request", Dtu::method_control_request, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "method_01",
  "action": "stop"
})", true},
    // 8.2.26. Fixed: trailing space in "method_01 ".
    {"8.2.26_method_control_response", Dtu::method_control_response, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "method_01",
  "code": "OK"
})", true},
    // 8.2.27. Fixed: missing comma after "guid"; trailing space in "dev_uuid ".
    {"8.2.27_event_register_request", Dtu::event_register_request, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "010302",
  "filters": [
    {"type": "range", "from": 10, "to": 20},
    {"type": "equal", "value": 100}
  ],
  "triggerType": "always"
})", true},
    // 8.2.28 (as printed).
    {"8.2.28_event_register_response", Dtu::event_register_response, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "event_01",
  "code": "OK"
})", true},
    // 8.2.29. Fixed: trailing space in "dev_uuid ".
    {"8.2.29_event_unregister_request", Dtu::event_unregister_request, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "event_01"
})", true},
    // 8.2.30 (as printed).
    {"8.2.30_event_unregister_response", Dtu::event_unregister_response, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "code": "NG",
  "reason": "Permission Denied",
  "error": 301
})", true},
    // 8.2.31. Fixed: "//" comment after "time" removed; missing comma after
    // "index"; "index" is a number (table 48), not "1"; trailing space in "event_01 ".
    {"8.2.31_event_data", Dtu::event_data, R"({
  "@id": "some_mid_001",
  "guid": "dev_uuid",
  "id": "event_01",
  "time": 19202912,
  "event": { "id": "012023", "index": 1, "oldValue": 10, "value": 5 }
})", true},
    // 8.3.4 / 8.3.5: no example is printed; built from the sample values of tables 53/54.
    {"8.3.4_dev_unreachable", Dtu::dev_unreachable, R"({
  "@id": "some_mid_123",
  "dev_uuid": "dev_uuid_2",
  "cli_uuid": "ex_cid",
  "code": "NG",
  "reason": "DEV_UNREACHABLE",
  "error": 301
})", true},
};
// clang-format on

}  // namespace chapter8
