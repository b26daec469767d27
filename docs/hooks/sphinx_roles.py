"""Griffe extension: Sphinx cross-reference roles in docstrings become mkdocstrings links.

The docstrings of ``rankedassign`` and ``oracle`` use the Sphinx roles that ``help()`` and
numpydoc readers know (``:func:`sample_original```, ``:class:`~rankedassign.AssignmentProblem```,
``:attr:`Prepared.kind <rankedassign.engine.result.Prepared>```). mkdocstrings does not read
them, so this extension rewrites them, in the documentation build only, into autorefs
cross-references ``[`sample_original`][rankedassign.samplers.sample_original]``. The source
files are not touched.

Resolution follows Sphinx's Python domain: a name is looked up in the enclosing class, then in
the docstring's module and its parent packages (including names they import), then as a full
path; ``.name`` with no such match is a suffix of exactly one object's path. The link goes to
the object where the API pages render it, else to the nearest enclosing object they render (a
field without a docstring to its record, a constant bound by ``A, B = 1, 2`` or an attribute
set outside ``__init__`` to its module or class, a private module to its package).

A role whose target is not found becomes a link without a target, which autorefs reports
where a page shows it, with the docstring's file and line: a strict build fails. A private
docstring that no page shows is not an error (the build logs it at level INFO, ``mkdocs build
-v``). Names outside the documented packages have no entry on this site: Python's builtins and
the packages listed in ``external`` render as code, not as links; any other name is an error.
"""

from __future__ import annotations

import ast
import builtins
import logging
import re
import textwrap
from pathlib import Path
from typing import Any

import griffe

_logger = logging.getLogger("mkdocs.plugins.rankedassign.sphinx_roles")

ROLES = ("func", "class", "meth", "mod", "data", "attr", "obj", "exc", "const")
# :role:`target`, :role:`~target`, :role:`text <target>`; optional "py:" domain prefix
ROLE = re.compile(
    r":(?:py:)?(?P<role>" + "|".join(ROLES) + r"):`(?P<body>[^`]+)`"
)
DIRECTIVE = re.compile(
    r"^:::[ \t]+(?P<name>[\w.]+)[ \t]*\n(?P<options>(?:[ \t]+\S.*\n?)*)", re.MULTILINE
)
EXPLICIT = re.compile(r"^(?P<text>.*?)\s*<(?P<target>[^<>]+)>$", re.DOTALL)


def _strip_call(target: str) -> str:
    return target[:-2] if target.endswith("()") else target


class SphinxRoles(griffe.Extension):
    """Rewrite Sphinx roles of the given packages' docstrings into autorefs links."""

    def __init__(
        self,
        packages: list[str] | None = None,
        external: list[str] | None = None,
        api_pages: str | None = None,
        package_pages: dict[str, str] | None = None,
    ):
        super().__init__()
        self.packages = tuple(packages or ())
        self.external = tuple(external or ())
        # the modules the API pages render (their "::: module" directives), and those of them
        # rendered with "members: false" (the module's docstring only)
        self.rendered_modules: set[str] = set()
        self.headers_only: set[str] = set()
        folder = Path(api_pages) if api_pages else Path(__file__).parents[1] / "api"
        for page in folder.glob("*.md"):
            for m in DIRECTIVE.finditer(page.read_text()):
                self.rendered_modules.add(m.group("name"))
                if re.search(r"^\s+members:\s*(false|\[\])\s*$", m.group("options") or "",
                             re.MULTILINE):
                    self.headers_only.add(m.group("name"))
        # a package without a directive: a page of the API folder that describes it
        self.package_pages = dict(package_pages or {})
        self._paths: list[str] | None = None
        self._aliases: dict[str, str] | None = None
        self.n_roles = 0
        self.n_unresolved = 0
        self._pending: list[griffe.Module] = []
        self._loading = False

    # -- griffe hook -------------------------------------------------------------------------
    def on_package(self, *, pkg: griffe.Module, loader: griffe.GriffeLoader, **kwargs: Any) -> None:
        if self.packages and pkg.name not in self.packages:
            return
        self._collection = loader.modules_collection
        self._pending.append(pkg)
        if self._loading:
            return
        # A docstring of one package may name an object of another: load them all first.
        self._loading = True
        try:
            for name in self.packages:
                if name not in self._collection.members:
                    loader.load(name)
        finally:
            self._loading = False
        while self._pending:
            self._walk(self._pending.pop(0))
        _logger.info("Sphinx roles: %d rewritten, %d without a target", self.n_roles,
                     self.n_unresolved)

    def _walk(self, obj: griffe.Object) -> None:
        for member in list(obj.members.values()):
            if member.is_alias:
                continue  # its docstring belongs to the object it points to
            self._rewrite(member)
            if member.is_module or member.is_class:
                self._walk(member)
        if obj.is_module and obj.parent is None:
            self._rewrite(obj)

    def _rewrite(self, obj: griffe.Object) -> None:
        doc = obj.docstring
        if doc is None or ":" not in doc.value:
            return
        new = ROLE.sub(lambda m: self._link(obj, m), doc.value)
        if new != doc.value:
            doc.value = new
            doc.__dict__.pop("parsed", None)  # drop a cached parse of the old text

    # -- one role ----------------------------------------------------------------------------
    def _link(self, obj: griffe.Object, match: re.Match) -> str:
        self.n_roles += 1
        body = match.group("body").strip()
        explicit = EXPLICIT.match(body)
        if explicit:
            text, target = explicit.group("text"), explicit.group("target").strip()
        else:
            text, target = None, body
        short = target.startswith("~")
        target = _strip_call(target.lstrip("~"))
        if text is None:
            text = target.rsplit(".", 1)[-1] if short else target
        path = self._resolve(obj, target)
        if path is None:
            if self._is_external(target):
                return f"`{text}`"
            # A link without a target: autorefs fails the strict build where the page shows
            # it (a private docstring that no page shows is not an error).
            self.n_unresolved += 1
            _logger.info("%s: %s does not resolve", obj.path, match.group(0))
            return f"[`{text}`][{target}]"
        if path in self.package_pages:
            # a plain link, relative to the API pages (the only pages that render docstrings);
            # mkdocs checks it and its anchor in strict mode
            return f"[`{text}`]({self.package_pages[path]})"
        return f"[`{text}`][{path}]"

    def _is_external(self, target: str) -> bool:
        head = target.split(".", 1)[0]
        if "." not in target and hasattr(builtins, target):
            return True  # int, TypeError, isinstance: Python's own, no entry on this site
        return any(head == e or target.startswith(e + ".") for e in self.external)

    def _lookup(self, path: str) -> griffe.Object | griffe.Alias | None:
        try:
            found = self._collection[path]
        except (KeyError, ValueError, griffe.AliasResolutionError, griffe.CyclicAliasError):
            return None
        if found.is_alias:
            try:
                found.final_target  # noqa: B018 - an alias to an object outside the collection
            except (griffe.AliasResolutionError, griffe.CyclicAliasError):
                return None
        return found

    def _resolve(self, obj: griffe.Object, target: str) -> str | None:
        """The path of the documented object ``target`` names in ``obj``'s docstring."""
        relative = target.startswith(".")
        target = target.lstrip(".")
        scopes = []
        scope: griffe.Object | None = obj if (obj.is_class or obj.is_module) else obj.parent
        while scope is not None:
            scopes.append(scope)
            scope = scope.parent
        for prefix in [*(s.path for s in scopes), ""]:
            path = f"{prefix}.{target}" if prefix else target
            found = self._lookup(path)
            if found is not None:
                return self._documented(found)
        if relative:
            # Sphinx: ".name" with no exact match is a suffix of some object's path
            matches = [p for p in self._all_paths() if p.endswith("." + target)]
            if len(matches) == 1:
                return self._documented(self._lookup(matches[0]))
        # griffe does not see every binding (``A, B = 1, 2``; ``self.x = ...`` outside
        # ``__init__``): a name the scope's source binds links to that scope
        head, _, rest = target.partition(".")
        for scope in scopes:
            if not rest and _binds(scope, head):
                return self._documented(scope)
        return None

    def _all_paths(self) -> list[str]:
        if self._paths is None:
            self._paths = []
            stack = [self._collection[name] for name in self.packages
                     if name in self._collection.members]
            while stack:
                obj = stack.pop()
                if obj.is_alias:
                    continue
                self._paths.append(obj.path)
                stack.extend(obj.members.values())
        return self._paths

    def _public_alias(self, path: str) -> str | None:
        """A public path (an import into a public module) of the object at ``path``."""
        if self._aliases is None:
            self._aliases = {}
            stack = [self._collection[name] for name in self.packages
                     if name in self._collection.members]
            while stack:
                obj = stack.pop()
                for member in obj.members.values():
                    if member.is_alias:
                        if _public(member.path):
                            self._aliases.setdefault(member.target_path, member.path)
                    elif member.is_module or member.is_class:
                        stack.append(member)
        return self._aliases.get(path)

    def _documented(self, found: griffe.Object | griffe.Alias) -> str:
        """The path of ``found`` on the API pages, else of its nearest rendered parent."""
        target = found.final_target if found.is_alias else found
        while True:
            public = target.path if _public(target.path) else self._public_alias(target.path)
            if public is not None and self._rendered(target, public):
                return public
            if target.parent is None:
                return target.path  # a package: an anchor on the API index names it
            target = target.parent

    def _rendered(self, obj: griffe.Object, public: str) -> bool:
        """Whether the API pages show ``obj`` (at ``public``) with the site's options."""
        if obj.is_module:
            return public in self.rendered_modules
        if obj.docstring is None:
            return False  # mkdocstrings shows no member without a docstring
        parts = public.split(".")
        for n in range(len(parts) - 1, 0, -1):
            module = ".".join(parts[:n])
            if module in self.rendered_modules:
                return module not in self.headers_only
        return False


def _public(path: str) -> bool:
    return not any(part.startswith("_") for part in path.split("."))


def _binds(scope: griffe.Object, name: str) -> bool:
    """Whether the source of a module (top level) or a class (``self.name =``) binds ``name``."""
    try:
        tree = ast.parse(textwrap.dedent(scope.source))
    except (SyntaxError, ValueError, OSError, TypeError):
        return False
    if scope.is_module:
        nodes = [t for stmt in tree.body if isinstance(stmt, (ast.Assign, ast.AnnAssign))
                 for t in (stmt.targets if isinstance(stmt, ast.Assign) else [stmt.target])]
        names = [n for t in nodes for n in ast.walk(t) if isinstance(n, ast.Name)]
        return any(n.id == name for n in names)
    if scope.is_class:
        return any(
            isinstance(n, ast.Attribute) and isinstance(n.ctx, ast.Store) and n.attr == name
            and isinstance(n.value, ast.Name) and n.value.id == "self"
            for n in ast.walk(tree)
        )
    return False
