#!/usr/bin/env python3
"""Large scenes and what a run may take (issue 21 items 17 and 19; docs/user/getting_started.md,
"Memory", and docs/user/input.md, "Encoding").

One case per invocation (--case), each generating its scenes in a temporary directory:

- linear_groups: --check-input of 1000 and of 4000 &load groups. Reading was quadratic in the
  groups (each appended to a copy of all before it: 4000 took 25-45 s, 12 times 1000); linear
  reading makes the ratio about 3 (a start-up of ~0.4 s is common to both), a quadratic one 16.
  Bound: ratio < 6.
- stack: a 4 MB scene read with a 1 MB stack limit, from the file and from a pipe. The lexer's
  automatic arrays (the text and a line number per character) crashed with a segfault as soon
  as the scene exceeded the stack; the pipe was read by appending each line to a copy of all
  before it.
- check_memory: --check-input of a 10^6-element rod, peak RSS against that of a 10-element rod.
  The plan built every rod at full size (~46 KB per element: 46 GB here; 4.7 GB measured at
  10^5); it now builds 3 and 4 elements and extends the sizes. Bound: at most 1.5 times the
  10-element check (measured: both ~43 MB). An address-space limit of 4 GB keeps a regression
  from taking the machine's memory.
- estimate: the memory estimate of the plan against the peak RSS of real runs (2 steps, one
  rank) of ph_director, ph_planar and se3_strand rods: within a factor 2 (the model and its
  measured constants: src/formulations/memory_estimate.f90).
- refusal: a run whose estimate exceeds RODSOLVE_MEMORY_LIMIT (100 MB for a ~430 MB run) and
  one of 10^8 elements (estimated ~13 TB, beyond this machine) are refused before anything is
  allocated or written: exit status 2, the message names the estimate and what is available,
  no output file; the same scene with a limit it fits runs.
- utf8: a scene in UTF-8 with non-ASCII text (title, comment) runs and output.md's h5py recipe
  reads /input/text back as the file's text; the same scene in Latin-1 is refused with file,
  line and byte (tests/input/bad/non_utf8.nml checks the message through run_input_case.py).
"""
import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile
import time

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
ENV.pop("RODSOLVE_MEMORY_LIMIT", None)

MATERIAL = ("EA = 1e4, GA1 = 1e4, GA2 = 1e4, EI1 = 10, EI2 = 10, GJ = 10, rhoA = 1, "
            "rhoI1 = 1e-3, rhoI2 = 1e-3")


def scene(n_elements=8, n_loads=0, formulation="ph_director", steps=2, title="big",
          path="out.h5", padding=0, force=1e-6):
    """A clamped rod with `n_loads` end loads (the i-th of `force` i), `padding` bytes of
    comment lines at the end."""
    text = (f"&run title = '{title}', formulation_default = '{formulation}' /\n"
            f"&time t_end = {steps * 0.01:.2f}, dt = 0.01 /\n"
            f"&output path = '{path}', xdmf = .false. /\n"
            f"&rod name = 'beam', n_elements = {n_elements}, length = 1.0, direction = 1, 0, 0,\n"
            f"    {MATERIAL} /\n"
            "&bc rod = 'beam', end = 'start', kind = 'clamped' /\n")
    text += "".join(f"&load rod = 'beam', where = 'end', force = 0, {-force * (i + 1):g}, 0 /\n"
                    for i in range(n_loads))
    line = "! " + "x" * 77 + "\n"
    text += line * max(0, (padding - len(text)) // len(line))
    return text


def run(command, cwd, stack=None, address_space=None, stdin=None, env=None):
    """Run `command`; returns (status, output, seconds, peak RSS in bytes) of that process."""
    def limits():
        if stack:
            resource.setrlimit(resource.RLIMIT_STACK, (stack, stack))
        if address_space:
            resource.setrlimit(resource.RLIMIT_AS, (address_space, address_space))
    started = time.monotonic()
    process = subprocess.Popen(command, cwd=cwd, env=env or ENV, stdin=stdin,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               preexec_fn=limits)
    output = process.stdout.read().decode("utf-8", "replace")
    _, status, usage = os.wait4(process.pid, 0)
    seconds = time.monotonic() - started
    process.stdout.close()
    process.returncode = os.waitstatus_to_exitcode(status)
    return process.returncode, output, seconds, usage.ru_maxrss * 1024


def write(workdir, name, text, encoding="utf-8"):
    path = os.path.join(workdir, name)
    with open(path, "w", encoding=encoding) as f:
        f.write(text)
    return path


def estimate_bytes(output):
    """The plan's "memory: estimated peak X on rank ..." in bytes."""
    match = re.search(r"memory: estimated peak ([0-9.]+) (MB|GB|TB) on rank", output)
    if not match:
        return None
    return float(match.group(1)) * {"MB": 1e6, "GB": 1e9, "TB": 1e12}[match.group(2)]


def case_linear_groups(rodsolve, workdir, failures):
    seconds = {}
    for n in (1000, 4000):
        path = write(workdir, f"loads{n}.nml", scene(n_loads=n))
        # The faster of two runs, against the load of a shared machine.
        for _ in range(2):
            status, output, elapsed, _ = run([rodsolve, "--check-input", path], workdir)
            if status != 0:
                failures.append(f"{n} loads: exit status {status}: {output[-2000:]}")
                return
            seconds[n] = min(seconds.get(n, elapsed), elapsed)
    ratio = seconds[4000] / seconds[1000]
    print(f"1000 &load groups: {seconds[1000]:.2f} s, 4000: {seconds[4000]:.2f} s, "
          f"ratio {ratio:.1f} (linear ~3, quadratic ~16; bound 6)")
    if ratio >= 6.0:
        failures.append(f"reading 4000 &load groups took {ratio:.1f} times as long as 1000 "
                        f"(bound 6: linear reading)")


def case_stack(rodsolve, workdir, failures):
    stack = 1 << 20
    path = write(workdir, "big.nml", scene(n_loads=20, padding=4 << 20))
    size = os.path.getsize(path)
    status, output, seconds, _ = run([rodsolve, "--check-input", path], workdir, stack=stack)
    print(f"{size} bytes with a {stack} byte stack, from the file: status {status}, "
          f"{seconds:.2f} s")
    if status != 0 or "is valid" not in output:
        failures.append(f"a {size}-byte scene with a 1 MB stack: exit status {status}: "
                        f"{output[-2000:]}")
    with open(path, "rb") as f:
        status, output, seconds, _ = run([rodsolve, "--check-input", "/dev/stdin"], workdir,
                                         stack=stack, stdin=f)
    print(f"the same from a pipe: status {status}, {seconds:.2f} s")
    if status != 0 or "is valid" not in output:
        failures.append(f"a {size}-byte scene from a pipe with a 1 MB stack: exit status "
                        f"{status}: {output[-2000:]}")
    elif seconds > 20:
        failures.append(f"a {size}-byte scene from a pipe took {seconds:.1f} s (bound 20 s)")


def case_check_memory(rodsolve, workdir, failures):
    rss = {}
    for n in (10, 1000000):
        path = write(workdir, f"e{n}.nml", scene(n_elements=n))
        status, output, _, rss[n] = run([rodsolve, "--check-input", path], workdir,
                                        address_space=4 << 30)
        print(f"--check-input of {n} elements: status {status}, peak RSS {rss[n] / 1e6:.0f} MB")
        if status != 0:
            failures.append(f"--check-input of {n} elements: exit status {status}: "
                            f"{output[-2000:]}")
            return
        if n == 1000000 and "1000000 elements of degree 2, 2000001 nodes" not in output:
            failures.append("the plan of 10^6 elements does not state its mesh")
    if rss[1000000] > 1.5 * rss[10]:
        failures.append(f"--check-input of 10^6 elements took {rss[1000000] / 1e6:.0f} MB, "
                        f"more than 1.5 times the {rss[10] / 1e6:.0f} MB of 10 elements")


def case_estimate(rodsolve, workdir, failures):
    for formulation, n in (("ph_director", 2000), ("ph_planar", 20000), ("se3_strand", 8000)):
        path = write(workdir, f"{formulation}.nml",
                     scene(n_elements=n, formulation=formulation, n_loads=1,
                           path=f"{formulation}.h5", force=1e-3))
        status, output, _, _ = run([rodsolve, "--check-input", path], workdir)
        estimate = estimate_bytes(output)
        if status != 0 or estimate is None:
            failures.append(f"{formulation}: the plan states no memory estimate "
                            f"(status {status}): {output[-2000:]}")
            continue
        status, output, seconds, rss = run([rodsolve, path], workdir)
        ratio = estimate / rss
        # A step that needs no Newton iteration never factors the Jacobian: no peak to compare.
        if re.search(r" 0 Jacobians factored", output):
            failures.append(f"{formulation}: no Jacobian was factored: {output[-2000:]}")
        print(f"{formulation}, {n} elements: estimated {estimate / 1e6:.0f} MB, measured peak "
              f"RSS {rss / 1e6:.0f} MB (ratio {ratio:.2f}), run {seconds:.1f} s, status {status}")
        if status != 0:
            failures.append(f"{formulation}: the run failed: {output[-2000:]}")
        elif not 0.5 <= ratio <= 2.0:
            failures.append(f"{formulation}: estimate {estimate / 1e6:.0f} MB is not within a "
                            f"factor 2 of the measured {rss / 1e6:.0f} MB")


def case_refusal(rodsolve, workdir, failures):
    path = write(workdir, "limited.nml", scene(n_elements=2000, path="limited.h5"))
    limited = dict(ENV, RODSOLVE_MEMORY_LIMIT="100e6")
    status, output, _, _ = run([rodsolve, path], workdir, env=limited, address_space=4 << 30)
    print(f"2000 elements with RODSOLVE_MEMORY_LIMIT = 100e6: status {status}")
    expected = ["the run needs an estimated", "but 100 MB are available to it "
                "(RODSOLVE_MEMORY_LIMIT = 100e6 bytes per rank)", "rod 'beam'", "nothing was run"]
    check_refused(output, status, expected, os.path.join(workdir, "limited.h5"), "limit",
                  failures)
    status, output, _, _ = run([rodsolve, path], workdir,
                               env=dict(ENV, RODSOLVE_MEMORY_LIMIT="4e9"), address_space=4 << 30)
    if status != 0:
        failures.append(f"2000 elements within a 4 GB limit: exit status {status}: "
                        f"{output[-2000:]}")
    path = write(workdir, "absurd.nml", scene(n_elements=100000000, path="absurd.h5"))
    status, output, seconds, rss = run([rodsolve, path], workdir, address_space=4 << 30)
    print(f"10^8 elements: status {status}, {seconds:.2f} s, peak RSS {rss / 1e6:.0f} MB")
    check_refused(output, status, ["the run needs an estimated", "TB on rank 0",
                                   "(MemAvailable of /proc/meminfo)", "100000000 elements"],
                  os.path.join(workdir, "absurd.h5"), "absurd", failures)


def check_refused(output, status, expected, result, what, failures):
    if status != 2:
        failures.append(f"{what}: exit status {status}, expected 2 (refused): {output[-2000:]}")
    for fragment in expected:
        if fragment not in output:
            failures.append(f"{what}: '{fragment}' not in the output: {output[-2000:]}")
    if os.path.exists(result):
        failures.append(f"{what}: the refused run created {result}")


def case_utf8(rodsolve, workdir, failures):
    text = scene(title="poutre en porte-à-faux, ∂²u/∂t² ≠ 0", path="utf8.h5")
    text += "! commentaire : déformée, 応力\n"
    path = write(workdir, "utf8.nml", text)
    status, output, _, _ = run([rodsolve, path], workdir)
    if status != 0:
        failures.append(f"a UTF-8 scene: exit status {status}: {output[-2000:]}")
        return
    # output.md's recipe.
    reader = ("import h5py, sys\n"
              "with h5py.File(sys.argv[1], 'r') as f:\n"
              "    sys.stdout.buffer.write(f['input/text'].asstr()[()].encode('utf-8'))\n")
    stored = subprocess.run(["/usr/bin/python3", "-c", reader, os.path.join(workdir, "utf8.h5")],
                            capture_output=True)
    if stored.returncode != 0:
        failures.append("output.md's h5py recipe cannot read /input/text: " +
                        stored.stderr.decode("utf-8", "replace")[-2000:])
    elif stored.stdout.decode("utf-8") != text:
        failures.append("/input/text differs from the scene file")
    else:
        print("/input/text of a UTF-8 scene reads back through h5py as the file")
    latin_text = scene(title="poutre en porte-à-faux", path="latin1.h5")
    latin = write(workdir, "latin1.nml", latin_text, encoding="latin-1")
    byte = latin_text.encode("latin-1").index(b"\xe0") + 1
    status, output, _, _ = run([rodsolve, latin], workdir)
    print(f"the same scene in Latin-1: status {status}")
    check_refused(output, status, [f"latin1.nml:1: byte {byte} (column {byte}, value 0xE0) is "
                                   "not valid UTF-8"], os.path.join(workdir, "latin1.h5"),
                  "Latin-1", failures)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--rodsolve", required=True)
    parser.add_argument("--case", required=True,
                        choices=["linear_groups", "stack", "check_memory", "estimate",
                                 "refusal", "utf8"])
    args = parser.parse_args()
    failures = []
    with tempfile.TemporaryDirectory() as workdir:
        globals()["case_" + args.case](os.path.abspath(args.rodsolve), workdir, failures)
    for failure in failures:
        print("FAIL: " + failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
