#!/usr/bin/env python3
"""isoterra — the walls between app/'s folders hold (app/meson.build,
docs/ARCHITECTURE.md "Dependencies point one way").

For each folder, the compile command the build really uses for one of its
sources (compile_commands.json) compiles a small probe file instead: a
probe that includes the door header of a folder below must compile, one
that includes a folder above, or a header of another folder that is not
its door, must fail with the header not found.  Both ways, so that a build
that lost its walls fails here, and so does one whose walls shut a door.

Also: no source of app/ climbs out of its folder with "../" (the only
includes that do are the door folders' forwarding headers), and each door
folder holds its door header and nothing else to include.

usage: test_walls.py BUILD_DIR SOURCE_DIR
"""
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile

# (folder, header, compiles): folder "main" is app/main.c, "app" the rest of
# app/'s top level
PROBES = [
    # a door of a folder below: compiles
    ('params', 'core.h', True),
    ('params', 'platform.h', True),
    ('gpu', 'params.h', True),
    ('gpu', 'hal.h', True),
    ('extract', 'gpu.h', True),
    ('edit', 'gpu.h', True),
    ('terrain', 'extract.h', True),
    ('terrain', 'edit.h', True),
    ('render', 'terrain.h', True),
    ('render', 'core.h', True),
    ('scene', 'render.h', True),
    ('output', 'scene.h', True),
    ('app', 'output.h', True),
    ('probe', 'output.h', True),
    ('main', 'app.h', True),
    ('main', 'probe.h', True),
    # the wrong way: a folder above
    ('core', 'render.h', False),
    ('core', 'params.h', False),
    ('params', 'gpu.h', False),
    ('gpu', 'extract.h', False),
    ('extract', 'terrain.h', False),
    ('extract', 'edit.h', False),
    ('edit', 'extract.h', False),
    ('terrain', 'render.h', False),
    ('render', 'scene.h', False),
    ('scene', 'output.h', False),
    ('output', 'app.h', False),
    ('output', 'probe.h', False),
    ('probe', 'app.h', False),
    ('app', 'probe.h', False),
    # past a door: another folder's other headers, its private ones
    ('params', 'log.h', False),
    ('gpu', 'util.h', False),
    ('extract', 'abi.h', False),
    ('terrain', 'field.h', False),
    ('terrain', 'edits.h', False),
    ('terrain', 'extract_int.h', False),
    ('render', 'pipeline.h', False),
    ('render', 'gpu_int.h', False),
    ('scene', 'density_ref.h', False),
    ('scene', 'curves_internal.h', False),
    ('scene', 'render_int.h', False),
    ('output', 'world.h', False),
    ('app', 'osd.h', False),
    ('app', 'sink.h', False),
    ('probe', 'controls.h', False),
    ('main', 'probe_int.h', False),
    ('main', 'world_int.h', False),
]

# each folder's door header(s), the only header of its door folder
DOORS = {'core': 'core.h', 'params': 'params.h', 'gpu': 'gpu.h', 'extract': 'extract.h', 'edit': 'edit.h',
         'terrain': 'terrain.h', 'render': 'render.h', 'scene': 'scene.h', 'output': 'output.h',
         'probe': 'probe.h', 'app': 'app.h'}

failed = 0
passed = 0


def check(ok, msg):
    global failed, passed
    if ok:
        passed += 1
    else:
        failed += 1
        print('FAIL ' + msg)


def args_of(entry):
    return entry['arguments'] if 'arguments' in entry else shlex.split(entry['command'])


def folder_of(entry):
    """The folder whose library (app/meson.build) or program (main.c) the
    entry compiles for, from its object's path; None for the others
    (tests/, bench/, the fuzzers: not the program's)."""
    args = args_of(entry)
    obj = args[args.index('-o') + 1] if '-o' in args else ''
    m = re.match(r'app/libapp_(\w+)\.a\.p/', obj)
    if m:
        return m.group(1)
    return 'main' if obj.startswith('isoterra.p/') else None


def probe_command(entry, probe):
    """The entry's compiler command with the probe as its source: -fsyntax-only,
    no object or dependency file."""
    args = args_of(entry)
    out, skip = [], False
    src = os.path.normpath(os.path.join(entry['directory'], entry['file']))
    for a in args:
        if skip:
            skip = False
            continue
        if a in ('-o', '-MF', '-MQ', '-MT'):
            skip = True
            continue
        if a in ('-c', '-MD', '-MMD'):
            continue
        if os.path.normpath(os.path.join(entry['directory'], a)) == src:
            continue
        out.append(a)
    return out + ['-fsyntax-only', probe]


def main():
    build, source = sys.argv[1], sys.argv[2]
    with open(os.path.join(build, 'compile_commands.json')) as f:
        db = json.load(f)
    entries = {}
    for e in db:
        fo = folder_of(e)
        if fo and fo not in entries:
            entries[fo] = e
    for fo in list(DOORS) + ['main']:
        check(fo in entries, 'no compile command for a source of folder ' + fo)

    tmp = tempfile.mkdtemp(prefix='isoterra-walls-')
    for i, (fo, header, compiles) in enumerate(PROBES):
        if fo not in entries:
            continue
        e = entries[fo]
        probe = os.path.join(tmp, 'walls_probe_%d.c' % i)
        with open(probe, 'w') as f:
            f.write('#include "%s"\nint walls_probe(void);\nint walls_probe(void) { return 0; }\n' % header)
        try:
            r = subprocess.run(probe_command(e, probe), cwd=e['directory'], capture_output=True, text=True)
        finally:
            os.unlink(probe)
        r.stderr = re.sub(r'\x1b\[[0-9;]*[mK]', '', r.stderr)  # the build's -fdiagnostics-color
        what = '%s including "%s"' % (fo, header)
        if compiles:
            check(r.returncode == 0, what + ' should compile:\n' + r.stderr)
        else:
            not_found = header in r.stderr and ('No such file' in r.stderr or 'not found' in r.stderr)
            check(r.returncode != 0 and not_found, what + ' should fail, header not found; got exit %d:\n%s'
                  % (r.returncode, r.stderr))
            if r.returncode != 0:
                err = [ln for ln in r.stderr.splitlines() if 'error' in ln][:1]
                print('  %-8s "%s": %s' % (fo, header, err[0][err[0].index('error'):] if err else ''))
    os.rmdir(tmp)

    # no include climbs out of its folder, but the doors' forwarding headers
    app = os.path.join(source, 'app')
    for dirpath, dirs, files in os.walk(app):
        in_door = os.path.basename(dirpath) == 'door'
        for name in files:
            if not name.endswith(('.c', '.h')):
                continue
            with open(os.path.join(dirpath, name)) as f:
                text = f.read()
            rel = os.path.relpath(os.path.join(dirpath, name), source)
            for inc in re.findall(r'#\s*include\s*"([^"]*)"', text):
                if in_door:
                    check(inc == '../' + name, rel + ': a door forwards to its header and nothing else: ' + inc)
                else:
                    check('/' not in inc, rel + ': includes "%s": a header of another folder comes through '
                          'its door, by name' % inc)
            if in_door:
                folder = os.path.basename(os.path.dirname(dirpath))
                check(name == DOORS.get(folder), rel + ': not the folder\'s door')
    for fo, door in DOORS.items():
        d = os.path.join(app, 'door') if fo == 'app' else os.path.join(app, fo, 'door')
        headers = sorted(n for n in os.listdir(d) if n.endswith('.h'))
        check(headers == [door], '%s: its door folder holds %s, not %s' % (d, headers, [door]))

    print('walls: %d passed, %d failed' % (passed, failed))
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
