"""Layer 9b, editor: ``kinetostatics edit FILE``, a live editor in the browser.

The server (:mod:`.server`) keeps one mechanism file (:mod:`.session`), answers the page's
requests with the problems ``kinetostatics check`` gives (:mod:`.problems`) and one JSON
document per analysis (:mod:`.snapshot`), computed by the same engine as ``run``
(``load``, ``analyze``); the page (``page/``: HTML, JavaScript, CSS, no network) draws it
(docs/editor.md).
"""
