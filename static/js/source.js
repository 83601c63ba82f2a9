// The page's sensor source, "phone" or "board" (the address's source=…, which the wizard templates
// put on their root as data-source; any other page: a phone's), and its words from the server's
// tables (app/web/tables.py SOURCES): the one place the pages' phone and board words come from.
import { TABLES } from "./tables.js";

const root = document.querySelector("[data-source]");
export const SOURCE = root && root.dataset.source === "board" ? "board" : "phone";
export const WORDS = TABLES.sources[SOURCE];
