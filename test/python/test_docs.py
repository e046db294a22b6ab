"""What a new user reads first is complete and points at files that exist:
- every relative link of README.md and docs/**/*.md resolves, and no source, config or doc file
  names SPEC.md (not in the repository; the specification is docs/spec.md);
- the ROS reference's launch-argument table (docs/reference/ros.md) lists every mode
  closed_loop.launch takes, its topic table every topic compare.launch records, and its attention
  row every field of AttentionEvent; the README's table of modes lists every mode."""

import glob
import os
import re
import unittest

from pkg_path import ROOT

SKIP_DIRS = {'.git', 'build', 'out', '__pycache__'}
TEXT_EXT = ('.md', '.py', '.cpp', '.hpp', '.yaml', '.msg', '.launch', '.cmake', '.sh', '.txt')


def _text_files():
    for d, dirs, files in os.walk(ROOT):
        dirs[:] = [x for x in dirs if x not in SKIP_DIRS]
        for f in files:
            p = os.path.join(d, f)
            if f.endswith(TEXT_EXT) or os.path.dirname(p) == os.path.join(ROOT, 'scripts'):
                yield p


class TestDocsLinks(unittest.TestCase):
    def test_relative_links_resolve(self):
        docs = [os.path.join(ROOT, 'README.md')] + _doc_pages()
        broken = []
        for doc in docs:
            with open(doc, encoding='utf-8') as f:
                text = f.read()
            for target in re.findall(r'\]\(([^)\s]+)\)', text):
                if re.match(r'[a-z]+:', target):
                    continue  # a web address: not checked offline
                path, _, anchor = target.partition('#')
                path = os.path.join(os.path.dirname(doc), path) if path else doc
                if not os.path.exists(path):
                    broken.append('%s -> %s' % (os.path.relpath(doc, ROOT), target))
                elif anchor and path.endswith('.md') and anchor not in _anchors(path):
                    broken.append(
                        '%s -> %s (no such heading)' % (os.path.relpath(doc, ROOT), target)
                    )
        self.assertEqual(broken, [])

    def test_anchors_follow_github(self):
        # the slugs test_relative_links_resolve checks links against
        self.assertEqual(
            _slug('Runtime tuning (dynamic_reconfigure)'), 'runtime-tuning-dynamic_reconfigure'
        )
        self.assertEqual(
            _slug('pa_robust: report seeds (from research/robust.md, Results)'),
            'pa_robust-report-seeds-from-researchrobustmd-results',
        )

    def test_specification_is_in_the_repository(self):
        self.assertTrue(os.path.isfile(os.path.join(ROOT, 'docs', 'spec.md')))
        naming = []
        for p in _text_files():
            with open(p, encoding='utf-8', errors='replace') as f:
                if 'SPEC.md' in f.read() and not p.endswith('test_docs.py'):
                    naming.append(os.path.relpath(p, ROOT))
        self.assertEqual(naming, [], 'files naming SPEC.md, which is not in the repository')


def _slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r'[`*]', '', heading.strip().lower())
    return re.sub(r'[^\w\- ]', '', text).replace(' ', '-')


def _anchors(page):
    """The anchors of a page's headings (a repeated heading gets -1, -2, ...)."""
    seen, out = {}, set()
    in_code = False
    with open(page, encoding='utf-8') as f:
        for line in f:
            if line.startswith('```'):
                in_code = not in_code
            if in_code or not re.match(r'#{1,6} ', line):
                continue
            slug = _slug(line.lstrip('#'))
            n = seen.get(slug, 0)
            seen[slug] = n + 1
            out.add(slug if n == 0 else '%s-%d' % (slug, n))
    return out


def _doc_pages():
    """Every page under docs/, sorted."""
    pages = []
    for d, dirs, files in os.walk(os.path.join(ROOT, 'docs')):
        pages += [os.path.join(d, f) for f in files if f.endswith('.md')]
    return sorted(pages)


def _readme():
    with open(os.path.join(ROOT, 'README.md'), encoding='utf-8') as f:
        return f.read()


def _ros_md():
    with open(os.path.join(ROOT, 'docs', 'reference', 'ros.md'), encoding='utf-8') as f:
        return f.read()


def _row(text, first_cell):
    rows = [ln for ln in text.splitlines() if ln.startswith('| %s |' % first_cell)]
    if not rows:
        raise AssertionError('no table row for %s' % first_cell)
    return rows[0]


class TestReadmeTables(unittest.TestCase):
    def test_mode_argument_lists_every_mode(self):
        # the launch files' `mode` docs point to the table; the docs' rows list its modes
        from preadaptive_mrac import modes as modes_table

        row = _row(_ros_md(), '`mode`')
        cells = re.findall(r'[a-z0-9_]+', row.split('|')[3])
        self.assertEqual([m for m in modes_table.MODES if m not in cells], [], row)
        # the README's table of modes: one row a mode, its first cell the mode's name
        readme_modes = re.findall(r'^\| `([a-z0-9_]+)` \|', _readme(), re.M)
        self.assertEqual([m for m in modes_table.MODES if m not in readme_modes], [], 'README.md')

    def test_topic_table_lists_every_recorded_topic(self):
        with open(os.path.join(ROOT, 'launch', 'compare.launch'), encoding='utf-8') as f:
            block = re.search(r'<rosparam param="topics">\[([^\]]*)\]', f.read()).group(1)
        # The pairs' topics, relative (rac/plant/state) since compare.launch runs in a namespace.
        topics = {re.sub(r'^/?(rac|pa)/', '', t.strip()) for t in block.split(',')}
        text = _ros_md()
        # A global name may be listed relative (`tf`: the namespace's own in a namespace).
        missing = [
            t for t in sorted(topics) if not any('| `%s` |' % n in text for n in (t, t.lstrip('/')))
        ]
        self.assertEqual(missing, [])

    def test_attention_row_names_every_field(self):
        with open(os.path.join(ROOT, 'msg', 'AttentionEvent.msg'), encoding='utf-8') as f:
            fields = []
            for line in f:
                parts = line.split('#')[0].split()
                if len(parts) == 2 and '=' not in parts[1] and parts[1] != 'header':
                    fields.append(parts[1])
        row = _row(_ros_md(), '`controller/attention`')
        self.assertIn('decision_code', fields)
        self.assertEqual([x for x in fields if '`%s`' % x not in row], [], row)


# The pages a user reads: the project's history (issue numbers, dated runs) goes to
# docs/notebook.md, not here.
USER_PAGES = [
    'README.md',
    'docs/research/reproduction.md',
    'docs/research/mismatch.md',
    'docs/jsbsim.md',
]
USER_DIRS = ['docs/tutorials', 'docs/reference', 'docs/research']
ISSUE_NUMBER = re.compile(r'\bissues?[\s_-]*#?\s*\d+|(?<![\w&/])#\d+\b', re.IGNORECASE)


def _user_pages():
    pages = [os.path.join(ROOT, p) for p in USER_PAGES]
    for d in USER_DIRS:
        pages += sorted(glob.glob(os.path.join(ROOT, d, '*.md')))
    return pages


class TestUserPages(unittest.TestCase):
    def test_no_issue_numbers(self):
        found = []
        for page in _user_pages():
            with open(page, encoding='utf-8') as f:
                for n, line in enumerate(f, 1):
                    for m in ISSUE_NUMBER.finditer(line):
                        found.append('%s:%d: %s' % (os.path.relpath(page, ROOT), n, m.group(0)))
        self.assertEqual(found, [], 'issue numbers in user pages (history: docs/notebook.md)')

    def test_pattern_finds_issue_numbers(self):
        for text in (
            'issue 36',
            'issue-22 report',
            'Issue 22 item 3',
            "issues 20 and 22",
            'see #41',
        ):
            self.assertTrue(ISSUE_NUMBER.search(text), text)
        for text in ('scenario 3', '&#39;', 'page.md#section-2', 'seed 1729'):
            self.assertFalse(ISSUE_NUMBER.search(text), text)

    def test_readme_short_with_a_licence_section(self):
        text = _readme()
        self.assertLessEqual(len(text.splitlines()), 200)
        self.assertIn('## Licence', text.splitlines())


class TestPlantConfigSaysWhereItFlies(unittest.TestCase):
    # A and B are Heffley and Jewell's condition 9 (Mach 0.8, 40,000 ft), where JSBSim trims
    # (plant.jsbsim.altitude_ft); the paper's "6000 m" is not where they come from.
    def test_b747_operating_point(self):
        import yaml

        for rel in ('config/plant/b747.yaml', 'test/ros/config/jsbsim_plant.yaml'):
            with open(os.path.join(ROOT, rel), encoding='utf-8') as f:
                text = f.read()
            plant = yaml.safe_load(text)['plant']
            self.assertIn('40,000 ft', plant['description'], rel)
            self.assertAlmostEqual(plant['operating_point']['h'], 40000 * 0.3048, 0, rel)
            self.assertNotIn('at 6000 m', text, rel)


if __name__ == '__main__':
    unittest.main()
