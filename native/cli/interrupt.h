// Ctrl-C handling: the signal handler only sets a flag; the loop that polls a running job
// sees it and calls bakegi_job_cancel, so the job stops cleanly and nothing is half-written.
#pragma once

namespace bakegi::cli {

void install_interrupt_handler();  // SIGINT and SIGTERM
bool interrupt_requested();

}  // namespace bakegi::cli
