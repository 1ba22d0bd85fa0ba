from agents.references.validation import main

main()
