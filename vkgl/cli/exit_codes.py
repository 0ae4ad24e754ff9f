"""The exit codes of `vkgc` (README, docs/errors.md): one table, used by every sub-command."""

EXIT_OK = 0
EXIT_INPUT = 1  # errors in the input, usage errors included
EXIT_NO_PLAN = 2  # `solve`: no plan within the search limits
EXIT_TIMEOUT = 3  # `solve`: the search ran out of time
EXIT_INTERNAL = 4  # a bug: one line says so, `--debug` shows the traceback
EXIT_NOT_REACHED = 5  # `solve --execute`: carried out in physics, the plan missed its goal
EXIT_INTERRUPTED = 130  # Ctrl-C
EXIT_PIPE_CLOSED = 141  # 128 + SIGPIPE: the reader of stdout/stderr went away (`| head -1`); work finished
EXIT_TERMINATED = 143  # 128 + SIGTERM (`timeout`, a scheduler): ended at once as Ctrl-C ends it
