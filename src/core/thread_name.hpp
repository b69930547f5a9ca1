// Names the calling thread (Linux: at most 15 characters, longer names are
// cut), so `top -H`, `ps -T` and debuggers show which part of nclink a thread
// is: in a gateway with hundreds of machines that is how a busy or stuck
// thread is found.
#pragma once

#include <pthread.h>

#include <string>

namespace nclink::core_detail {

inline void name_this_thread(const std::string& name) {
    const std::string cut = name.substr(0, 15);
    pthread_setname_np(pthread_self(), cut.c_str());
}

}  // namespace nclink::core_detail
