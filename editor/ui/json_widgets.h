// ImGui widgets bound to a value in the document by JSON pointer. A change is
// one undoable Document::set; while the widget stays active (a drag, typing)
// the edits merge into one undo step (merge key = the widget's ImGui ID).
// Each widget registers a ui_mark under its JSON pointer for UI scripts.
#pragma once
#include <initializer_list>
#include <string>
#include <vector>

namespace pliant::editor {

class Document;

bool json_double(Document& doc, const char* label, const std::string& ptr, double def,
                 float speed = 0.01f, double lo = 0, double hi = 0, const char* fmt = "%.4g");
bool json_int(Document& doc, const char* label, const std::string& ptr, int def, int lo = 0,
              int hi = 0);
bool json_choice(Document& doc, const char* label, const std::string& ptr, const char* def,
                 std::initializer_list<const char*> choices);
bool json_choice(Document& doc, const char* label, const std::string& ptr, const char* def,
                 const std::vector<std::string>& choices);
// A fixed-size array of numbers (dim 2 or 3), shown as DragScalarN.
bool json_vec(Document& doc, const char* label, const std::string& ptr, int dim, float speed = 0.01f);
bool json_text(Document& doc, const char* label, const std::string& ptr);
bool json_bool(Document& doc, const char* label, const std::string& ptr, bool def);
// Generic editor for any JSON value (objects and arrays as tree nodes).
void json_tree(Document& doc, const std::string& label, const std::string& ptr);

}  // namespace pliant::editor
