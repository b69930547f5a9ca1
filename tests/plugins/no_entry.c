/* A shared library that is not an nclink plugin. */
__attribute__((visibility("default"))) int something_else(void) { return 42; }
