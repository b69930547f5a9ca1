// An adapter's statistics in the Prometheus text exposition format
// (docs/metrics.md): AdapterStats, the sampling statistics (lateness
// histograms per channel), DTUs in and out by kind and the request latency
// histogram. libnclink serves no HTTP: a program that wants a /metrics
// endpoint serves this text itself (nclink-sim --metrics does, with the
// project's HTTP server; firmware usually leaves it off).
//
//   std::string text = nclink::prometheus_metrics(adapter);
//
// Thread-safe (reads the adapter's thread-safe statistics).
#pragma once

#include <nclink/adapter.hpp>
#include <nclink/export.hpp>

#include <string>
#include <vector>

namespace nclink {

/// One adapter's metrics, every sample labelled dev="<its terminal id>".
NCLINK_API std::string prometheus_metrics(const Adapter& adapter);
/// Several adapters of one process in one exposition (each metric family
/// once, a sample per adapter). Null entries are skipped.
NCLINK_API std::string prometheus_metrics(const std::vector<const Adapter*>& adapters);

}  // namespace nclink
