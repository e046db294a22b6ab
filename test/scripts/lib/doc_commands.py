"""The shell commands of the README's quick start and of the tutorials, as one bash script per
page, for test/scripts/docs_commands.sh.

    doc_commands.py PAGE BUILD    # prints the script; each left-out command as a comment with
                                  # its reason, and "# SKIPPED: <reason>" lines on stderr

A command is a line of a ```sh block (a trailing backslash joins the next line; a heredoc runs
to its end marker), or a whole ```python block (run by /usr/bin/python3, ROS's, within
PYTHON_TIMEOUT s: a snippet that waits without end fails). The commands SKIPS matches are left
out, each with its reason; every other command runs, in page order, in one bash session that
starts at the repository root. A command BACKGROUND matches is a run the reader leaves going in
one shell while typing the next commands in a second: it runs in the background, the page goes
on once its controller serves dynamic_reconfigure, and a command that reads what the run wrote
(AFTER_BACKGROUND) waits for its end. Commands that need such a run (NEEDS_RUN) are left out
only on pages without one.
"""

import re
import shlex
import sys

# Left out, with the reason: (pattern on the command, reason). A pattern matching a command
# that no longer appears in any page is itself an error (docs_commands.sh checks it).
SKIPS = [
    (
        r'^scripts/run_demo\b',
        'the whole demo (1-4 min): test/scripts/run_demo_keeps_outputs.sh runs it',
    ),
    (r'^scripts/test\b', 'the whole test suite, which runs this test'),
    (r'^scripts/install_deps\b', 'apt-get as root: scripts/test and scripts/run_demo run it'),
    (r'^sudo apt-get\b', 'apt-get as root: installing git, before the clone'),
    (
        r'^git clone\b',
        'the clone itself (the test runs in one); test/scripts/catkin_workspace.sh builds a '
        'workspace from a clone',
    ),
    (
        r'^(mkdir -p ~/catkin_ws|rosdep install|catkin_make|catkin build|source devel/setup.bash)',
        'a catkin workspace from a clone: test/scripts/catkin_workspace.sh builds one',
    ),
    (
        r'clock:=realtime',
        'a realtime run (60 s) with windows or waiting for Ctrl-C; rviz, live_plot and realtime '
        'runs: test/viz/rviz_screenshot_test.sh, test/scripts/live_plot.sh, '
        'test/ros/realtime*.test',
    ),
    (
        r'^rosrun preadaptive_mrac live_plot\b',
        'a window that runs until closed: test/scripts/live_plot.sh',
    ),
    (
        r'^rosrun dynamic_reconfigure dynparam\b',
        'needs the realtime run above, left out: test/ros/reconfigure.test changes parameters of a '
        'running controller',
    ),
]
# Skipped only where the page has no background run.
NEEDS_RUN = [r'^rosrun dynamic_reconfigure dynparam\b']
# A realtime run without windows that ends by itself, with commands for a second shell after it.
BACKGROUND = [
    r'^roslaunch preadaptive_mrac scenario\.launch clock:=realtime mode:=\w+ record:=true'
]
# Reads the bag of the background run: waits for the run's end.
AFTER_BACKGROUND = [r'~/tuning/']
PYTHON_TIMEOUT = 60
STOP_ON_EXIT = 'trap \'kill -INT "$PMRAC_BACKGROUND" 2>/dev/null && wait "$PMRAC_BACKGROUND"\' EXIT'
# The background run's controller serves dynamic_reconfigure (then the second shell starts).
WAIT_SERVED = (
    'for _ in $(seq 240); do rosservice list 2>/dev/null | grep -q '
    '"mrac_controller/reconfigure/set_parameters" && break; sleep 0.5; done'
)


def blocks(text):
    """The ```sh and ```python blocks of a page: [(first line number, language, [lines])]."""
    out, cur, start, lang = [], None, 0, None
    for n, line in enumerate(text.splitlines(), 1):
        if cur is None and line.strip() in ('```sh', '```python'):
            cur, start, lang = [], n + 1, line.strip()[3:]
        elif cur is not None and line.strip() == '```':
            out.append((start, lang, cur))
            cur = None
        elif cur is not None:
            cur.append(line)
    return out


def commands(lines):
    """Lines joined into commands: backslash continuations, heredocs to their end marker."""
    out, i = [], 0
    while i < len(lines):
        cmd = lines[i]
        i += 1
        while cmd.endswith('\\') and i < len(lines):
            cmd += '\n' + lines[i]
            i += 1
        m = re.search(r"<<-?\s*'?(\w+)'?", cmd)
        if m:
            while i < len(lines):
                cmd += '\n' + lines[i]
                i += 1
                if lines[i - 1].strip() == m.group(1):
                    break
        if cmd.strip() and not cmd.lstrip().startswith('#'):
            out.append(cmd)
    return out


def skip_reason(cmd, background):
    for pattern, reason in SKIPS:
        if background and any(re.search(p, cmd) for p in NEEDS_RUN):
            continue
        if re.search(pattern, cmd):
            return pattern, reason
    return None, None


def python_command(lines):
    """A ```python block as one shell command."""
    body = '\n'.join(lines)
    return "timeout %d /usr/bin/python3 - <<'PMRAC_PYTHON'\n%s\nPMRAC_PYTHON" % (
        PYTHON_TIMEOUT,
        body,
    )


def script(page, build):
    """The bash script of a page and the skip patterns it used."""
    with open(page, encoding='utf-8') as f:
        text = f.read()
    used = set()
    out = ['set -eE -o pipefail', 'trap \'echo "FAILED: $BASH_COMMAND" >&2\' ERR']
    background = False
    for start, lang, lines in blocks(text):
        cmds = [python_command(lines)] if lang == 'python' else commands(lines)
        for cmd in cmds:
            first = cmd.splitlines()[0] if lang == 'sh' else 'python: ' + lines[0]
            if any(re.search(p, cmd) for p in BACKGROUND):
                background = True
                out.append(
                    'echo %s' % shlex.quote('+ %s:%d: (background) %s' % (page, start, first))
                )
                out.append('%s > "$HOME/background_run.log" 2>&1 &' % cmd)
                out.append('PMRAC_BACKGROUND=$!')
                # a page that fails before the run's end stops the run
                out.append(STOP_ON_EXIT)
                out.append(WAIT_SERVED)
                continue
            if background and any(re.search(p, cmd) for p in AFTER_BACKGROUND):
                out.append('wait "$PMRAC_BACKGROUND"')
                background = False
            pattern, reason = skip_reason(cmd, background)
            if reason:
                used.add(pattern)
                sys.stderr.write('# SKIPPED: %s:%d: %s -- %s\n' % (page, start, first, reason))
                out.append('# skipped (%s): %s' % (reason, first))
                continue
            # the README's build folder is the test's (PMRAC_BUILD_DIR)
            cmd = cmd.replace('source build/devel/setup.bash', 'source %s/devel/setup.bash' % build)
            out.append('echo %s' % shlex.quote('+ %s:%d: %s' % (page, start, first)))
            out.append(cmd)
    if background:
        out.append('wait "$PMRAC_BACKGROUND"')
    return '\n'.join(out) + '\n', used


def main():
    if sys.argv[1] == '--patterns':
        # every skip pattern, one a line (docs_commands.sh checks each is still used)
        print('\n'.join(p for p, _ in SKIPS))
        return
    if sys.argv[1] == '--used':
        # the skip patterns the given pages use
        used = set()
        for page in sys.argv[2:]:
            used |= script(page, 'build')[1]
        print('\n'.join(sorted(used)))
        return
    sys.stdout.write(script(sys.argv[1], sys.argv[2])[0])


if __name__ == '__main__':
    main()
