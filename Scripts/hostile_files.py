"""Hostile files at scale (docs/robustness.md): damaged copies of real state files, each read
in a child process with a time limit, and a table of what came of them.

  /usr/bin/python3 Scripts/hostile_files.py <build> [--copies 1000] [--seed 34] [--timeout 20]
                                          [--jobs 2] [--keep <dir>]

<build> is a build folder with bin/read_state_file (target read_state_file; a Release build,
or build-asan/ for AddressSanitizer's eyes on each read). The sources, all in the repository:

- v3, one writer: Testing/Fuzz/corpus/super-helix.h5 (Core's Simulation, SWMR, HDF5's latest
  format; Scripts/make_fuzz_corpus.py);
- v3, 2 ranks: Testing/Fixtures/StateFiles/v3-shared-super-helix.h5 (written by 2 MPI ranks
  together: HDF5's earliest format, /whole_frames);
- v2, 2 ranks: Testing/Fixtures/StateFiles/v2-super-helix.h5 (the same, format version 2).

Each copy is damaged in one of five ways, in turn (copy i takes kind i % 5), at places drawn
by a generator seeded with (seed, source, i), so that any copy is made again alike:

- one byte: one byte anywhere XORed with a random non-zero value;
- 2-16 bytes: as many bytes anywhere, each XORed;
- first 4 KiB: 1-8 bytes XORed within the first 4 KiB (the superblock, the root group and
  its attributes, the first object headers);
- metadata: 1-8 bytes XORed among the bytes that hold no dataset's values (object headers,
  B-trees, heaps, wherever they are; located with h5py in the undamaged source);
- truncated: the file cut at a random length, 0 to its size less one byte.

Each copy is read by `read_state_file` (opened, every frame read whole and as the 2 pieces of
2 ranks, each drawn as Hair State Reader draws it), in a child with the time limit, and
classified: read whole; refused (exit 1 with "refused: <message>"); crash (a signal, or an
AddressSanitizer, LeakSanitizer or UndefinedBehaviorSanitizer report); hang (the time
limit); unclear (a refusal whose message is empty, does not name the copy, or says nothing
beside the name; any other exit). Crashes, hangs and unclear refusals fail the run (exit 1)
and their copies are kept in --keep (default <build>/hostile-files/) to replay:
`<build>/bin/read_state_file <copy>`, or under gdb.
"""
import argparse
import collections
import concurrent.futures
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

try:
    import h5py
except ImportError:
    sys.exit("hostile_files: needs h5py (Debian's python3-h5py: /usr/bin/python3)")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCES = [
    ("v3, one writer", "Testing/Fuzz/corpus/super-helix.h5"),
    ("v3, 2 ranks", "Testing/Fixtures/StateFiles/v3-shared-super-helix.h5"),
    ("v2, 2 ranks", "Testing/Fixtures/StateFiles/v2-super-helix.h5"),
]
KINDS = ["one byte", "2-16 bytes", "first 4 KiB", "metadata", "truncated"]
SANITIZER = re.compile(r"ERROR: (Address|Leak|Memory|Thread)Sanitizer|runtime error:")
# HDF5's own note at exit (and its list of the objects it still held) after a refused file
# that leaked its references (docs/robustness.md, "The fuzzer"): not an error of the read.
HDF5_AT_EXIT = "HDF5: infinite loop closing library"


def metadata_spans(path):
    """The byte ranges [begin, end) of `path` that hold no dataset's values: HDF5's metadata
    (superblock, object headers, B-trees, heaps) and free space, as h5py locates the values."""
    values = []

    def visit(_, obj):
        if not isinstance(obj, h5py.Dataset):
            return
        if obj.chunks:
            for k in range(obj.id.get_num_chunks()):
                chunk = obj.id.get_chunk_info(k)
                values.append((chunk.byte_offset, chunk.byte_offset + chunk.size))
        elif obj.id.get_offset() is not None:  # contiguous; compact values are in the header
            values.append((obj.id.get_offset(), obj.id.get_offset() + obj.id.get_storage_size()))

    with h5py.File(path, "r") as f:
        f.visititems(visit)
    spans, at = [], 0
    for begin, end in sorted(values):
        if begin > at:
            spans.append((at, begin))
        at = max(at, end)
    size = os.path.getsize(path)
    if at < size:
        spans.append((at, size))
    return spans


def damage(data, spans, seed, source, index):
    """The copy `index` of `data` (`spans`: its metadata_spans): its kind and its bytes."""
    rng = random.Random(f"{seed}/{source}/{index}")
    kind = KINDS[index % len(KINDS)]
    out = bytearray(data)
    if kind == "truncated":
        return kind, bytes(out[:rng.randrange(len(out))])
    if kind == "one byte":
        places = [rng.randrange(len(out))]
    elif kind == "2-16 bytes":
        places = [rng.randrange(len(out)) for _ in range(rng.randint(2, 16))]
    elif kind == "first 4 KiB":
        places = [rng.randrange(min(4096, len(out))) for _ in range(rng.randint(1, 8))]
    else:
        total = sum(end - begin for begin, end in spans)
        places = []
        for _ in range(rng.randint(1, 8)):
            k = rng.randrange(total)
            for begin, end in spans:
                if k < end - begin:
                    places.append(begin + k)
                    break
                k -= end - begin
    for at in places:
        out[at] ^= rng.randint(1, 255)
    return kind, bytes(out)


def clear(message, path):
    """A refusal a user can act on: it names the file and says, in words, what is wrong."""
    if path not in message:
        return False
    words = re.findall(r"[A-Za-z]{3,}", message.replace(path, ""))
    return len(words) >= 3


def read(reader, path, timeout, env):
    start = time.monotonic()
    try:
        run = subprocess.run([reader, path], capture_output=True, text=True, errors="replace",
                             timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return "hang", f"no answer in {timeout} s", time.monotonic() - start, ""
    seconds = time.monotonic() - start
    out, err = run.stdout.strip(), run.stderr.strip()
    if run.returncode < 0:
        name = signal.Signals(-run.returncode).name
        return "crash", f"{name}; {err[-2000:]}", seconds, err
    if SANITIZER.search(err):
        return "crash", err[-4000:], seconds, err
    if run.returncode == 0 and out.startswith("read whole:"):
        return "read whole", out, seconds, err
    if run.returncode == 1 and out.startswith("refused: "):
        message = out[len("refused: "):]
        return ("refused" if clear(message, path) else "unclear"), message, seconds, err
    return "unclear", f"exit {run.returncode}: {out} {err}"[:2000], seconds, err


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("build")
    parser.add_argument("--copies", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=34)
    parser.add_argument("--timeout", type=float, default=20)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--keep", help="where failing copies are kept")
    args = parser.parse_args()
    reader = os.path.join(os.path.abspath(args.build), "bin", "read_state_file")
    if not os.access(reader, os.X_OK):
        sys.exit(f"hostile_files: {reader} is missing: "
                 f"cmake --build {args.build} --target read_state_file")
    keep = args.keep or os.path.join(os.path.abspath(args.build), "hostile-files")
    env = dict(os.environ)
    env.setdefault("ASAN_OPTIONS", "halt_on_error=1:detect_leaks=1:allocator_may_return_null=1")
    env.setdefault("UBSAN_OPTIONS", "halt_on_error=1:print_stacktrace=1")
    env.setdefault("LSAN_OPTIONS", "suppressions=" + os.path.join(
        ROOT, "Testing/Sanitizers/lsan.supp") + ":print_suppressions=0")

    scratch = tempfile.mkdtemp(prefix="hair-hostile-")
    rows, failures, by_kind = [], [], collections.defaultdict(collections.Counter)
    started = time.monotonic()
    try:
        for name, relative in SOURCES:
            source = os.path.join(ROOT, relative)
            outcome, message, _, _ = read(reader, source, args.timeout, env)
            if outcome != "read whole":
                sys.exit(f"hostile_files: the undamaged source {relative} is not read whole: "
                         f"{message}")
            with open(source, "rb") as f:
                data = f.read()
            spans = metadata_spans(source)
            tag = os.path.splitext(os.path.basename(relative))[0]
            if "2 ranks" in name:
                tag = "mpi-" + tag

            def one(index):
                kind, bytes_ = damage(data, spans, args.seed, name, index)
                path = os.path.join(scratch, f"{tag}-{index:04d}.h5")
                with open(path, "wb") as f:
                    f.write(bytes_)
                outcome, message, seconds, err = read(reader, path, args.timeout, env)
                if outcome in ("crash", "hang", "unclear"):
                    os.makedirs(keep, exist_ok=True)
                    shutil.copy(path, keep)
                os.remove(path)
                return index, kind, path, outcome, message, seconds, err

            counts, messages = collections.Counter(), collections.Counter()
            slowest, noted, noisy = (0.0, None), 0, 0
            with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
                for index, kind, path, outcome, message, seconds, err in pool.map(
                        one, range(args.copies)):
                    counts[outcome] += 1
                    by_kind[kind][outcome] += 1
                    slowest = max(slowest, (seconds, index))
                    if err.startswith(HDF5_AT_EXIT):
                        noted += 1
                    elif err:
                        noisy += 1
                    if outcome == "refused":
                        messages[message.replace(path, "<copy>")] += 1
                    elif outcome != "read whole":
                        failures.append((name, index, kind, outcome, message,
                                         os.path.join(keep, os.path.basename(path))))
            rows.append((name, relative, len(data), counts, slowest, messages, noted, noisy))
            print(f"{name}: {dict(counts)}", file=sys.stderr, flush=True)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)

    print(f"Hostile files: {args.copies} damaged copies of each source, seed {args.seed}, "
          f"time limit {args.timeout:g} s, {args.jobs} at a time; "
          f"{time.monotonic() - started:.0f} s in all.\n")
    print("| source | copies | read whole | refused | crashes | hangs | unclear refusals "
          "| slowest child |")
    print("|---|---|---|---|---|---|---|---|")
    for name, relative, size, counts, slowest, _, _, _ in rows:
        print(f"| {name} (`{os.path.basename(relative)}`, {size} bytes) | {args.copies} "
              f"| {counts['read whole']} | {counts['refused']} | {counts['crash']} "
              f"| {counts['hang']} | {counts['unclear']} | {slowest[0]:.2f} s (copy {slowest[1]}) |")
    print("\nBy kind of damage, all sources:\n")
    print("| damage | read whole | refused | crashes | hangs | unclear |")
    print("|---|---|---|---|---|---|")
    for kind in KINDS:
        c = by_kind[kind]
        print(f"| {kind} | {c['read whole']} | {c['refused']} | {c['crash']} | {c['hang']} "
              f"| {c['unclear']} |")
    for name, _, _, _, _, messages, noted, noisy in rows:
        print(f"\n{name}: {len(messages)} different refusals; the most common "
              f"(<copy> is the damaged file's path):")
        for message, count in messages.most_common(4):
            print(f"  {count:4d} × {message}")
        print(f"  {noted} children printed HDF5's note at exit ({HDF5_AT_EXIT!r})")
        if noisy:
            print(f"  {noisy} children wrote to stderr beside their answer (other than "
                  f"HDF5's note at exit)")
    for name, index, kind, outcome, message, kept in failures:
        print(f"\nFAILED {outcome}: {name}, copy {index} ({kind}), kept as {kept}\n  {message}")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
