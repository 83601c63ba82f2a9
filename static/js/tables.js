// The constants the server shares with the pages (app/web/tables.py page_tables()), rendered into
// the page as JSON: the poses, the cube24 positions and turns, the capture thresholds. Python is
// their only source; this module reads them once.

const node = document.getElementById("trical-tables");
if (!node) throw new Error("this page has no #trical-tables: its route must render app.web.tables.page_tables()");

export const TABLES = JSON.parse(node.textContent);
