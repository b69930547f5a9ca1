/* Declares the controller API (hal_*) the guides' C examples call. Included
 * before every C block of the docs by check_doc_blocks.sh. */
#pragma once
int hal_open(void);
void hal_close(int handle);
int hal_spindle_rpm(void);
const char* hal_program_name(void);
int hal_tool_count(void);
double hal_tool_length(int tool);
