// Undo and redo of the page (issue 47). The YAML in the editor is the page's whole state, so
// the history is a list of texts: each change the page makes (a slider, a colour, a plugin, pan
// and zoom, reset and fit) records the text before it, and so does each burst of typing (the
// keystrokes of one pause). Undo puts the last recorded text back, and redo the one undone; a
// new change after an undo drops what could be redone, as every editor does.
'use strict';
/* exported EditHistory */

class EditHistory {
  constructor(limit = 500) {
    this.past = [];
    this.future = [];
    this.limit = limit;
  }

  // The text is about to change from `before`.
  record(before) {
    if (this.past.length && this.past[this.past.length - 1] === before) return;
    this.past.push(before);
    if (this.past.length > this.limit) this.past.shift();
    this.future = [];
  }

  // The text to go back to from `current`, or null when there is none.
  undo(current) {
    while (this.past.length) {
      const t = this.past.pop();
      if (t === current) continue; // (a recorded text the page came back to by itself)
      this.future.push(current);
      return t;
    }
    return null;
  }

  redo(current) {
    if (!this.future.length) return null;
    this.past.push(current);
    return this.future.pop();
  }

  clear() {
    this.past = [];
    this.future = [];
  }

  canUndo() {
    return this.past.length > 0;
  }

  canRedo() {
    return this.future.length > 0;
  }
}
