#pragma once
// What one row's map build makes and another row's can reuse within one bake of one surface:
// safety-sd's distances are safety-cc's radii, so `relief bake --maps safety-sd,safety-cc`
// computes them once. A product is keyed by its kind and everything that determines it (the
// builder spells the key out), built on first request and held until the share is destroyed
// (the end of the bake). Only bakes share: the bench times each row's build on its own.
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <typeinfo>
#include <utility>
#include <vector>

namespace relief {

class BuildShare {
public:
    // The product under `key` (of type T), from `build` the first time. `what` names it for
    // the bake report ("safety distances"), `producer` the row that built it.
    template <class T, class Build>
    std::shared_ptr<const T> get(const std::string& key, const std::string& what,
                                 const std::string& producer, Build&& build) {
        const std::string full = std::string(typeid(T).name()) + "|" + key;
        std::lock_guard<std::mutex> lock(m_mutex);
        if (auto it = m_products.find(full); it != m_products.end()) {
            m_notes.push_back(what + " from " + it->second.producer);
            return std::static_pointer_cast<const T>(it->second.product);
        }
        auto product = std::make_shared<const T>(build());
        m_products[full] = {product, producer};
        return product;
    }

    // What was reused since the last call ("safety distances from safety-sd"), for the report.
    std::vector<std::string> takeNotes() {
        std::lock_guard<std::mutex> lock(m_mutex);
        return std::exchange(m_notes, {});
    }

private:
    struct Entry {
        std::shared_ptr<const void> product;
        std::string producer;
    };
    std::mutex m_mutex;
    std::map<std::string, Entry> m_products;
    std::vector<std::string> m_notes;
};

}  // namespace relief
