/* A small C library whose one nclink_* function reaches every struct of the
 * C ABI (the options reach the driver descriptor, the descriptor every plugin
 * struct). c_abi_check.cmake builds it from the headers as they are and from
 * a copy with a field inserted, to prove that tools/check-c-abi.sh reports
 * such an insertion. */
#include <nclink/nclink.h>

__attribute__((visibility("default"))) int nclink_abi_probe(const nclink_adapter_options* options, nclink_error* error,
                                                            const nclink_value* values) {
    return options != NULL && error != NULL && values != NULL;
}
