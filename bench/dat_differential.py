#!/usr/bin/env python3
"""Differential test of `wearknit dat` against the reference `knitout-to-dat.js`.

Generates random knitout programs (fixed seeds), converts each with both
programs and checks that they take the same decision (accept / reject) and,
when both accept, write the same bytes. Prints every disagreement with its
seed and a summary; exit status 1 when there was any.

  bench/dat_differential.py [--build BUILD] [--first N] [--last M] [--kind mixed|sliders]
                            [--keep DIR]

Needs node and the reference script (KNITOUT_TO_DAT, default: the extracted
copy under /work/ref, see docs/dat.md). `mixed` programs: random carriers in
sets of one to three, inhook / releasehook / out / outhook, rackings (whole,
quarter pitch, beyond +-8), knits, tucks, misses, drops, a-misses, splits and
transfers with and without sliders, stitch / speed / presser settings, pauses.
`sliders` programs: quarter-pitch rows on both beds, two-carrier sets and
split-via-sliders blocks with their returns.
"""
import argparse
import os
import random
import subprocess
import sys
import tempfile

HEAD = [';!knitout-2', ';;Carriers: 1 2 3 4 5 6 7 8 9 10']


def mixed(seed):
    r = random.Random(seed)
    lines = list(HEAD)
    if r.random() < 0.3:
        lines.append(';;Position: ' + r.choice(['Left', 'Right', 'Center']))
    if r.random() < 0.2:
        lines.append(';;Width: ' + str(r.choice([20, 50, 100, 540])))
    sets = []  # {'cs': [...], 'used': bool, 'hook': bool}
    hook = None
    racking = 0
    width = r.choice([4, 8, 16, 30])
    lo = r.choice([0, -3, 5])

    def free():
        taken = {c for s in sets for c in s['cs']}
        return [str(c) for c in range(1, 11) if str(c) not in taken]

    def bring_in():
        f = free()
        k = 2 if (r.random() < 0.25 and len(f) >= 2) else 1
        if r.random() < 0.01:
            k = 3
        cs = r.sample(f, k)
        by_hook = r.random() < 0.5 and hook is None and not any(
            s['hook'] and not s['used'] for s in sets)
        lines.append(('inhook ' if by_hook else 'in ') + ' '.join(cs))
        sets.append(dict(cs=cs, used=False, hook=by_hook))

    def use(s):
        nonlocal hook
        if not s['used']:
            s['used'] = True
            if s['hook']:
                hook = s

    def release():
        nonlocal hook
        lines.append('releasehook ' + ' '.join(hook['cs']))
        hook['hook'] = False
        hook = None

    def needle():
        return r.choice('fb') + str(r.randint(lo - 1, lo + width))

    bring_in()
    for _ in range(r.randint(5, 150)):
        x = r.random()
        if x < 0.05 and len(sets) < 4:
            bring_in()
        elif x < 0.08:
            if hook is not None and r.random() < 0.7:
                release()
        elif x < 0.11:
            ready = [s for s in sets if s['used'] and not s['hook']]
            if ready:
                s = r.choice(ready)
                op = r.choice(['out', 'outhook']) if hook is None else 'out'
                lines.append(op + ' ' + ' '.join(s['cs']))
                sets.remove(s)
        elif x < 0.16:
            racking = r.choice([0, 0, 0, 1, -1, 2, -2, 0.25, -0.75, 1.25, 4, -4, 3, 9])
            lines.append('rack %s' % racking)
        elif x < 0.19:
            lines.append(r.choice([
                'x-stitch-number %d' % r.randint(0, 300), 'x-speed-number %d' % r.randint(0, 20),
                'x-presser-mode ' + r.choice(['on', 'off', 'auto']), 'stitch 10 15',
                'stitch 25 45', 'pause', 'x-foo 3', 'stitch -10 10']))
        elif x < 0.55:
            if sets:
                s = r.choice(sets)
                op = r.choice(['knit', 'knit', 'knit', 'tuck', 'miss'])
                lines.append('%s %s %s %s' % (op, r.choice('+-'), needle(), ' '.join(s['cs'])))
                use(s)
        elif x < 0.60:
            lines.append('%s %s' % (r.choice(['drop', 'amiss']), needle()))
        elif x < 0.72:
            if racking != int(racking):
                continue
            k = int(racking)
            n = r.randint(lo - 1, lo + width)
            a, b = r.choice([('f', 'b'), ('b', 'f'), ('f', 'b'), ('b', 'f'),
                             ('f', 'bs'), ('b', 'fs'), ('fs', 'b'), ('bs', 'f')])
            m = n - k if a[0] == 'f' else n + k
            if r.random() < 0.3 and sets and not a.endswith('s'):
                s = r.choice(sets)
                lines.append('split %s %s%d %s%d %s' % (r.choice('+-'), a, n, b, m, ' '.join(s['cs'])))
                use(s)
            else:
                lines.append('xfer %s%d %s%d' % (a, n, b, m))
        elif x < 0.80:
            if racking != int(racking):
                continue
            k = int(racking)
            a, b = r.choice([('f', 'b'), ('b', 'f')])
            for n in range(lo, lo + width):
                lines.append('xfer %s%d %s%d' % (a, n, b, n - k if a == 'f' else n + k))
        else:
            if sets:
                s = r.choice(sets)
                op = r.choice(['knit', 'knit', 'tuck'])
                d = r.choice('+-')
                ns = range(lo, lo + width) if d == '+' else range(lo + width - 1, lo - 1, -1)
                for n in ns:
                    if r.random() >= 0.2:
                        bed = 'b' if r.random() < 0.3 else 'f'
                        lines.append('%s %s %s%d %s' % (op, d, bed, n, ' '.join(s['cs'])))
                use(s)
    if hook is not None:
        release()
    for s in list(sets):
        if not s['used']:
            lines.append('knit + f%d %s' % (lo, ' '.join(s['cs'])))
            use(s)
            if hook is not None:
                release()
        lines.append(r.choice(['out ', 'outhook ']) + ' '.join(s['cs']))
    return '\n'.join(lines) + '\n'


def sliders(seed):
    r = random.Random(seed)
    lines = list(HEAD)
    if r.random() < 0.3:
        lines.append(';;Position: ' + r.choice(['Left', 'Right', 'Center', 'Keep']))
    width = r.choice([3, 6, 10])
    lo = r.choice([1, 2, 5])
    cs = r.sample([str(c) for c in range(1, 11)], 4)
    sets = [[cs[0]], [cs[1], cs[2]], [cs[3]]]
    for s in sets:
        lines.append('in ' + ' '.join(s))
    used = set()
    for _ in range(r.randint(3, 25)):
        x = r.random()
        s = r.choice(sets)
        d = r.choice('+-')
        ns = list(range(lo, lo + width))
        if d == '-':
            ns.reverse()
        if x < 0.35:
            lines.append('rack %s' % r.choice([0.25, -0.75, 0, 1.25]))
            for n in ns:
                for bed in (('f', 'b') if d == '+' else ('b', 'f')):
                    if r.random() < 0.7:
                        op = r.choice(['knit', 'tuck', 'miss'])
                        lines.append('%s %s %s%d %s' % (op, d, bed, n, ' '.join(s)))
            lines.append('rack 0')
            used.add(tuple(s))
        elif x < 0.55:
            base = r.choice([0, 1, -1])
            back = base + r.choice([1, 2, 4, -1, -2, -4, 3])
            lines.append('rack %d' % base)
            bed = r.choice('fb')
            split = []
            for n in ns:
                if r.random() < 0.6:
                    if bed == 'f':
                        lines.append('split %s f%d bs%d %s' % (d, n, n - base, ' '.join(s)))
                        split.append(('bs', n - base))
                    else:
                        lines.append('split %s b%d fs%d %s' % (d, n, n + base, ' '.join(s)))
                        split.append(('fs', n + base))
            used.add(tuple(s))
            if split:
                lines.append('rack %d' % back)
                r.shuffle(split)
                for slider, m in split:
                    if slider == 'bs':
                        lines.append('xfer bs%d f%d' % (m, m + back))
                    else:
                        lines.append('xfer fs%d b%d' % (m, m - back))
            lines.append('rack 0')
        elif x < 0.75:
            for n in ns:
                lines.append('knit %s %s%d %s' % (d, r.choice('fb'), n, ' '.join(s)))
            used.add(tuple(s))
        elif x < 0.85:
            k = r.choice([1, -1, 2])
            lines.append('rack %d' % k)
            for n in range(lo, lo + width):
                if r.random() < 0.5:
                    lines.append('xfer f%d b%d' % (n, n - k))
            lines.append('rack 0')
        else:
            lines.append(r.choice(['x-presser-mode auto', 'x-presser-mode on', 'x-presser-mode off',
                                   'x-speed-number 3', 'pause', 'stitch 20 20']))
    for s in sets:
        if tuple(s) not in used:
            lines.append('knit + f%d %s' % (lo, ' '.join(s)))
        lines.append('out ' + ' '.join(s))
    return '\n'.join(lines) + '\n'


def main():
    default_ref = ('/work/ref/interpreter/dat_compiler/dat-compiler/'
                   'knitout-backend-swg-master/knitout-to-dat.js')
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--build', default='build')
    parser.add_argument('--first', type=int, default=1)
    parser.add_argument('--last', type=int, default=200)
    parser.add_argument('--kind', choices=['mixed', 'sliders'], default='mixed')
    parser.add_argument('--keep', help='write disagreeing programs into this folder')
    args = parser.parse_args()
    reference = os.environ.get('KNITOUT_TO_DAT', default_ref)
    wearknit = os.path.join(args.build, 'apps', 'wearknit', 'wearknit')
    generate = mixed if args.kind == 'mixed' else sliders
    counts = {'both accept, same bytes': 0, 'both reject': 0, 'disagree': 0}
    with tempfile.TemporaryDirectory() as tmp:
        k, ref_dat, our_dat = (os.path.join(tmp, n) for n in ('p.k', 'r.dat', 'w.dat'))
        for seed in range(args.first, args.last + 1):
            program = generate(seed)
            with open(k, 'w') as f:
                f.write(program)
            for path in (ref_dat, our_dat):
                if os.path.exists(path):
                    os.remove(path)
            ref = subprocess.run(['node', reference, k, ref_dat], capture_output=True, text=True)
            ours = subprocess.run([wearknit, 'dat', k, '-o', our_dat], capture_output=True,
                                  text=True)
            if ref.returncode == 0 and ours.returncode == 0:
                with open(ref_dat, 'rb') as a, open(our_dat, 'rb') as b:
                    same = a.read() == b.read()
                problem = None if same else 'different bytes'
            elif ref.returncode != 0 and ours.returncode != 0:
                problem = None
            else:
                problem = 'reference exit %d, wearknit exit %d: %s' % (
                    ref.returncode, ours.returncode,
                    (ours.stderr if ours.returncode else ref.stderr).strip().splitlines()[-1:])
            if problem is None:
                counts['both accept, same bytes' if ref.returncode == 0 else 'both reject'] += 1
            else:
                counts['disagree'] += 1
                print('seed %d (%s): %s' % (seed, args.kind, problem))
                if args.keep:
                    os.makedirs(args.keep, exist_ok=True)
                    with open(os.path.join(args.keep, '%s-%d.k' % (args.kind, seed)), 'w') as f:
                        f.write(program)
    print('%s seeds %d..%d: %s' % (args.kind, args.first, args.last,
                                    ', '.join('%s %d' % kv for kv in counts.items())))
    return 1 if counts['disagree'] else 0


if __name__ == '__main__':
    sys.exit(main())
