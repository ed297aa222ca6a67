// Runs a wasm32-wasi program under Node.js's WASI (node:wasi, preview1) with
// the given arguments, stdout and stderr; exits with the program's status.
// certify.py's runner for the wasm32-wasi builds:
//   node --no-warnings vectors/certify/run_wasi.mjs PROGRAM.wasm [ARG...]
import { readFile } from "node:fs/promises";
import { argv, exit } from "node:process";
import { WASI } from "node:wasi";

if (argv.length < 3) {
  console.error("usage: node run_wasi.mjs PROGRAM.wasm [ARG...]");
  exit(2);
}
const wasi = new WASI({ version: "preview1", args: argv.slice(2), env: {}, returnOnExit: true });
const module = await WebAssembly.compile(await readFile(argv[2]));
const instance = await WebAssembly.instantiate(module, wasi.getImportObject());
exit(wasi.start(instance));
