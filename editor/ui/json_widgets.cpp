#include "ui/json_widgets.h"

#include <imgui.h>

#include <cstring>
#include <functional>
#include <vector>

#include "doc/document.h"
#include "ui/ui_mark.h"

namespace pliant::editor {

namespace {

using nlohmann::json;

const json* lookup(const Document& doc, const std::string& ptr) {
  json::json_pointer p(ptr);
  return doc.scene().contains(p) ? &doc.scene().at(p) : nullptr;
}

// The merge key: the widget's ID plus the pointer, so distinct fields never merge.
void commit(Document& doc, const std::string& ptr, const json& v, const char* label) {
  uint64_t key = (static_cast<uint64_t>(ImGui::GetID(label)) << 32) ^ std::hash<std::string>{}(ptr);
  doc.set(ptr, v, key | 1);
}

}  // namespace

bool json_double(Document& doc, const char* label, const std::string& ptr, double def, float speed,
                 double lo, double hi, const char* fmt) {
  const json* j = lookup(doc, ptr);
  double v = j && j->is_number() ? j->get<double>() : def;
  bool changed = ImGui::DragScalar(label, ImGuiDataType_Double, &v, speed, lo < hi ? &lo : nullptr,
                                   lo < hi ? &hi : nullptr, fmt);
  if (changed) commit(doc, ptr, v, label);
  ui_mark_field(ptr);
  return changed;
}

bool json_int(Document& doc, const char* label, const std::string& ptr, int def, int lo, int hi) {
  const json* j = lookup(doc, ptr);
  int v = j && j->is_number() ? j->get<int>() : def;
  bool changed = ImGui::DragInt(label, &v, 0.25f, lo, hi);
  if (changed) commit(doc, ptr, v, label);
  ui_mark_field(ptr);
  return changed;
}

bool json_choice(Document& doc, const char* label, const std::string& ptr, const char* def,
                 const std::vector<std::string>& choices) {
  const json* j = lookup(doc, ptr);
  std::string cur = j && j->is_string() ? j->get<std::string>() : def;
  bool changed = false;
  if (ImGui::BeginCombo(label, cur.c_str())) {
    for (const std::string& c : choices) {
      const bool picked = ImGui::Selectable(c.c_str(), cur == c);
      ui_mark(ptr + "=" + c);  // scripts pick a choice: click_item /optimizer/method=lbfgs
      if (picked && cur != c) {
        doc.set(ptr, c);
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  ui_mark_field(ptr);
  return changed;
}

bool json_choice(Document& doc, const char* label, const std::string& ptr, const char* def,
                 std::initializer_list<const char*> choices) {
  return json_choice(doc, label, ptr, def, std::vector<std::string>(choices.begin(), choices.end()));
}

bool json_vec(Document& doc, const char* label, const std::string& ptr, int dim, float speed) {
  const json* j = lookup(doc, ptr);
  double v[3] = {0, 0, 0};
  if (j && j->is_array())
    for (int i = 0; i < dim && i < static_cast<int>(j->size()); ++i)
      if ((*j)[i].is_number()) v[i] = (*j)[i].get<double>();
  bool changed = ImGui::DragScalarN(label, ImGuiDataType_Double, v, dim, speed, nullptr, nullptr, "%.3f");
  if (changed) commit(doc, ptr, json(std::vector<double>(v, v + dim)), label);
  ui_mark_field(ptr);
  return changed;
}

bool json_text(Document& doc, const char* label, const std::string& ptr) {
  const json* j = lookup(doc, ptr);
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s", j && j->is_string() ? j->get<std::string>().c_str() : "");
  bool changed = ImGui::InputText(label, buf, sizeof buf);
  if (changed) commit(doc, ptr, std::string(buf), label);
  ui_mark_field(ptr);
  return changed;
}

bool json_bool(Document& doc, const char* label, const std::string& ptr, bool def) {
  const json* j = lookup(doc, ptr);
  bool v = j && j->is_boolean() ? j->get<bool>() : def;
  bool changed = ImGui::Checkbox(label, &v);
  if (changed) doc.set(ptr, v);
  ui_mark_field(ptr);
  return changed;
}

void json_tree(Document& doc, const std::string& label, const std::string& ptr) {
  const json* j = lookup(doc, ptr);
  if (!j) return;
  ImGui::PushID(ptr.c_str());
  if (j->is_object() || j->is_array()) {
    std::string head = label + (j->is_array() ? " [" + std::to_string(j->size()) + "]" : "");
    if (ImGui::TreeNode(head.c_str())) {
      // Copy the keys: an edit below replaces the document this iterates.
      std::vector<std::string> keys;
      if (j->is_object()) {
        for (auto it = j->begin(); it != j->end(); ++it) keys.push_back(it.key());
      } else {
        for (size_t i = 0; i < j->size(); ++i) keys.push_back(std::to_string(i));
      }
      for (const auto& k : keys) json_tree(doc, k, ptr + "/" + k);
      if (j->is_array() && ImGui::SmallButton("+ element")) {
        json next = *j;
        next.push_back(next.empty() ? json(0.0) : next.back());
        doc.set(ptr, next);
      }
      ImGui::TreePop();
    }
  } else if (j->is_boolean()) {
    json_bool(doc, label.c_str(), ptr, false);
  } else if (j->is_number_integer()) {
    json_int(doc, label.c_str(), ptr, 0);
  } else if (j->is_number()) {
    json_double(doc, label.c_str(), ptr, 0.0);
  } else if (j->is_string()) {
    json_text(doc, label.c_str(), ptr);
  } else {
    ImGui::TextDisabled("%s: null", label.c_str());
  }
  ImGui::PopID();
}

}  // namespace pliant::editor
