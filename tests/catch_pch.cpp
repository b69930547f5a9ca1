// Compiled with the precompiled header: a target whose only source skips the
// PCH gets no PCH at all on a fresh configure, and every test binary reuses
// this one (REUSE_FROM nclink_catch_main).
#include <catch2/catch.hpp>
